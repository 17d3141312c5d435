// `esdslam report OUT [--groundtruth FILE] [--debug-frames DIR]`: writes OUT/report.html, one
// self-contained page about a finished run (report/run_report.h). Prints the page's path.
#include <cstdio>
#include <memory>
#include <string>

#include "apps/esdslam/commands.h"
#include "report/run_report.h"

namespace esdslam::cli {
namespace {

RunFn Setup(CLI::App& app) {
  auto options = std::make_shared<ReportOptions>();
  app.add_option("OUT", options->out_dir, "Output folder of `esdslam run` (trajectory.txt, timing.csv, ...)")
      ->required()
      ->check(CLI::ExistingDirectory);
  app.add_option("--groundtruth", options->groundtruth_path,
                 "Ground-truth trajectory (TUM format): adds the alignment, the error over time and the ATE/RPE")
      ->check(CLI::ExistingFile);
  app.add_option("--debug-frames", options->debug_frames_dir,
                 "The run's --debug-frames folder: a few of its pictures go into the page");
  app.add_option("--frames", options->max_debug_frames, "Debug pictures sampled into the page")
      ->check(CLI::Range(0, 50))
      ->capture_default_str();
  app.add_option("--crowded", options->crowded_fraction,
                 "Shade the frames whose dynamic_fraction exceeds this (people cover most of the image)")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  app.add_option("--max-dt", options->ate.max_time_difference,
                 "Max timestamp difference for associating poses with ground truth, seconds (as esdslam eval)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  return [options] {
    const std::string path = WriteRunReport(*options);
    std::printf("%s\n", path.c_str());
    return 0;
  };
}

const Registrar kRegistrar({"report", "Write OUT/report.html: one self-contained page about a finished run", Setup,
                            65});

}  // namespace
}  // namespace esdslam::cli
