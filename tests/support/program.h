#pragma once
// The built `esdslam` program and shell commands, for the tests that run them as a user would.
#include <string>

namespace esdslam::testing {

struct ShellResult {
  int exit_code = -1;  // -1: the command could not be started or did not exit normally
  std::string output;  // stdout and stderr, interleaved
};

std::string EsdslamProgram();  // BinaryDir()/esdslam
// Runs `command` with /bin/sh, stderr joined to stdout, and waits for it.
ShellResult RunShell(const std::string& command);
std::string ReadTextFile(const std::string& path);  // "" when the file cannot be read

}  // namespace esdslam::testing
