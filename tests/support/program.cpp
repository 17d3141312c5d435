#include "support/program.h"

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "support/test_paths.h"

namespace esdslam::testing {

std::string EsdslamProgram() { return (std::filesystem::path(BinaryDir()) / "esdslam").string(); }

ShellResult RunShell(const std::string& command) {
  ShellResult result;
  FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
  if (pipe == nullptr) return result;
  std::array<char, 4096> buffer;
  while (std::fgets(buffer.data(), buffer.size(), pipe) != nullptr) result.output += buffer.data();
  const int status = ::pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

std::string ReadTextFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

ShellResult RunShellInSourceDir(const std::string& command) {
  return RunShell("cd '" + SourceDir() + "' && " + command);
}

std::size_t DataLines(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::size_t count = 0;
  while (std::getline(in, line)) count += !line.empty() && line[0] != '#';
  return count;
}

}  // namespace esdslam::testing
