#pragma once
// Subcommands of the `esdslam` program register themselves here (one file per subcommand,
// cmd_<name>.cpp), so that adding a subcommand touches no other file.
//
// A subcommand's `setup` adds its options to the CLI11 sub-app and returns the function that
// runs it; that function returns the process exit status (0 = success). Library errors
// (esdslam::Error) escaping from it are reported by main() with exit status 1.

#include <functional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace esdslam::cli {

using RunFn = std::function<int()>;
using SetupFn = std::function<RunFn(CLI::App& subcommand)>;

struct Command {
  std::string name;
  std::string description;
  SetupFn setup;
  int order = 100;  // position in --help (lower first)
};

std::vector<Command>& Registry();

struct Registrar {
  explicit Registrar(Command command) { Registry().push_back(std::move(command)); }
};

}  // namespace esdslam::cli
