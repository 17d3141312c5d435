#pragma once
// The built `esdslam` program and shell commands, for the tests that run them as a user would.
#include <cstddef>
#include <string>

namespace esdslam::testing {

struct ShellResult {
  int exit_code = -1;  // -1: the command could not be started or did not exit normally
  std::string output;  // stdout and stderr, interleaved
};

std::string EsdslamProgram();  // BinaryDir()/esdslam
// Runs `command` with /bin/sh, stderr joined to stdout, and waits for it.
ShellResult RunShell(const std::string& command);
// The same, run in the source tree (relative model and vocabulary paths resolve there).
ShellResult RunShellInSourceDir(const std::string& command);
std::string ReadTextFile(const std::string& path);  // "" when the file cannot be read
// Lines of a text file that are neither empty nor '#' comments (poses in a TUM trajectory).
std::size_t DataLines(const std::string& path);

}  // namespace esdslam::testing
