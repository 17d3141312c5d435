// `esdslam view OUT [--port P] [--address A] [--debug-frames DIR]`: a finished run's output
// folder in the live viewer's page (viewer/run_replay.h), served until Ctrl-C (SIGINT/SIGTERM).
// Prints the page's address on stdout.
#include <cstdio>
#include <memory>
#include <string>

#include <spdlog/spdlog.h>

#include "apps/esdslam/commands.h"
#include "apps/esdslam/stop_signals.h"
#include "viewer/event_hub.h"
#include "viewer/run_replay.h"
#include "viewer/viewer_server.h"

namespace esdslam::cli {
namespace {

struct ViewArgs {
  ReplayInputs inputs;
  ViewerOptions options;
};

int View(const ViewArgs& args) {
  InstallStopSignals();
  EventHub hub;
  const RunFiles files = PublishRun(args.inputs, args.options, &hub);
  ViewerServer server(args.options, &hub);
  spdlog::info("view: {} frames, {} poses, {} keyframes; serving until Ctrl-C", files.timing.rows.size(),
               files.trajectory.size(), files.keyframes.size());
  std::printf("%s\n", server.url().c_str());
  std::fflush(stdout);
  WaitForStopSignal();
  server.Stop();
  return 0;
}

RunFn Setup(CLI::App& app) {
  auto args = std::make_shared<ViewArgs>();
  app.add_option("OUT", args->inputs.out_dir, "Output folder of `esdslam run` (trajectory.txt, timing.csv, ...)")
      ->required()
      ->check(CLI::ExistingDirectory);
  app.add_option("--port", args->options.port, "Serve the page on http://ADDRESS:PORT/ (0 = any free port)")
      ->check(CLI::Range(0, 65535))
      ->capture_default_str();
  app.add_option("--address", args->options.address, "The address to listen on")->capture_default_str();
  app.add_option("--debug-frames", args->inputs.debug_dir, "The run's --debug-frames folder: its last picture is shown");
  return [args] { return View(*args); };
}

const Registrar kRegistrar({"view", "Show a finished run's outputs in the live viewer's page", Setup, 25});

}  // namespace
}  // namespace esdslam::cli
