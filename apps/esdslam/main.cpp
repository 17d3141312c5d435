// esdslam: command-line entry point. See README.md "CLI reference".
#include <algorithm>
#include <csignal>
#include <cstdio>
#include <exception>
#include <map>
#include <memory>

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include "apps/esdslam/commands.h"
#include "common/error.h"

namespace esdslam::cli {
std::vector<Command>& Registry() {
  static std::vector<Command> commands;
  return commands;
}
}  // namespace esdslam::cli

int main(int argc, char** argv) {
  using namespace esdslam::cli;
  CLI::App app{"ESD-SLAM: RGB-D SLAM for scenes with moving people"};
  app.require_subcommand(1);
  bool verbose = false;
  app.add_flag("-v,--verbose", verbose, "Debug logging");

  auto commands = Registry();
  std::sort(commands.begin(), commands.end(),
            [](const Command& a, const Command& b) { return a.order != b.order ? a.order < b.order : a.name < b.name; });
  std::map<CLI::App*, RunFn> runners;
  for (const auto& command : commands) {
    CLI::App* sub = app.add_subcommand(command.name, command.description);
    runners[sub] = command.setup(*sub);
  }

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  // Every log line (info, warnings, errors) goes to stderr; stdout carries only results
  // (summaries, `eval --json`), so that `esdslam eval --json > r.json` is valid JSON.
  spdlog::set_default_logger(
      std::make_shared<spdlog::logger>("", std::make_shared<spdlog::sinks::stderr_color_sink_mt>()));
  spdlog::set_level(verbose ? spdlog::level::debug : spdlog::level::info);
  // A file-size limit (ulimit -f) or a full disk must be a write error naming the file, not a
  // kill by SIGXFSZ with a file cut off mid-line.
  std::signal(SIGXFSZ, SIG_IGN);
  try {
    for (const auto& [sub, run] : runners) {
      if (sub->parsed()) return run();
    }
  } catch (const esdslam::Error& e) {
    spdlog::error("{}", e.what());
    return 1;
  } catch (const std::exception& e) {
    spdlog::error("unexpected error: {}", e.what());
    return 2;
  }
  return 1;
}
