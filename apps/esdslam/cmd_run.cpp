// `esdslam run --settings FILE --sequence DIR --out DIR [--mode none|semantic|geometry|full]`: runs the SLAM
// system over a TUM-layout RGB-D sequence and writes trajectory.txt, keyframes.txt, timing.csv and
// settings_used.yaml (every stage's keys); with --dense also the dense map. The settings file and
// the flags are resolved here, once, into the run's configuration (system/run_config.h); the
// frames go through the pipeline by the run loop (system/run_loop.h).
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include <spdlog/spdlog.h>

#include "apps/esdslam/commands.h"
#include "common/error.h"
#include "common/timer.h"
#include "io/frame_source.h"
#include "io/tum_sequence.h"
#include "report/run_report.h"
#include "system/frame_log.h"
#include "system/pipeline.h"
#include "system/run_config.h"
#include "system/run_loop.h"
#include "system/run_outputs.h"
#include "system/run_settings.h"

namespace esdslam::cli {
namespace {

struct RunArgs {
  std::string settings_path;
  std::string mode = "full";
  RunFlags flags;
  bool report = false;  // --report: OUT/report.html at the end (report/run_report.h)
};

void ShowProgress(const FrameReport& report, std::size_t n, const SlamSystem& system, double elapsed_ms) {
  const std::size_t done = static_cast<std::size_t>(report.index) + 1;
  if (done % 10 != 0 && done != n) return;
  std::fprintf(stderr, "\rframe %zu/%zu  %.1f fps  %-15s  keyframes %d  map points %d   ", done, n,
               1000.0 * static_cast<double>(done) / std::max(1.0, elapsed_ms), ToString(report.track.state),
               system.num_keyframes(), system.num_map_points());
  if (done == n) std::fprintf(stderr, "\n");
}

// OUT/report.html, with the sequence's ground truth when it has one.
void WriteReport(const RunConfig& config, const std::string& summary) {
  ReportOptions options;
  options.out_dir = config.run.out_dir;
  const TumSequence sequence = TumSequence::Open(config.run.sequence_dir);
  if (sequence.has_groundtruth()) options.groundtruth_path = sequence.groundtruth_path();
  options.debug_frames_dir = config.run.debug_frames_dir;
  options.run_summary = summary;
  spdlog::info("run: report {}", WriteRunReport(options));
}

// Writes every result and prints the summary (and the report with --report); returns the exit status.
int Conclude(Pipeline& pipeline, const FrameLog& log, std::size_t total_frames, double loop_ms, bool failed,
             bool report) {
  const RunConfig& config = pipeline.config();
  WriteRunResults(pipeline, log, config.run.out_dir);
  const std::string summary = FormatRunSummary(log, total_frames, pipeline.system(), loop_ms);
  std::fputs(summary.c_str(), stdout);
  if (report) WriteReport(config, summary);
  if (failed) return 1;
  if (!config.run.save_map.empty()) pipeline.system().SaveMap(config.run.save_map);
  return 0;
}

int Run(RunArgs args) {
  RunSettings settings = LoadRunSettings(args.settings_path);
  const TumSequence sequence = TumSequence::Open(args.flags.run.sequence_dir);
  std::filesystem::create_directories(args.flags.run.out_dir);
  args.flags.mode = ParseDynamicMode(args.mode);
  const RunConfig config = ResolveRunConfig(std::move(settings), args.flags);
  LogRunConfig(config);
  std::size_t n = sequence.frames().size();
  if (config.run.max_frames > 0) n = std::min<std::size_t>(n, config.run.max_frames);
  TumFolderSource source({sequence.frames().begin(), sequence.frames().begin() + n},
                         config.settings.core.depth_map_factor);
  Pipeline pipeline(config);
  const std::string& debug_dir = config.run.debug_frames_dir;
  if (!debug_dir.empty()) std::filesystem::create_directories(debug_dir);
  FrameLog log;
  Stopwatch total;
  try {
    RunFrames(source, pipeline, [&](const FrameReport& report) {
      if (!debug_dir.empty()) WriteDebugFrame(debug_dir, report);
      log.Add(report);
      ShowProgress(report, n, pipeline.system(), total.ElapsedMs());
    });
  } catch (const Error& e) {
    std::fprintf(stderr, "\n");
    spdlog::error("run: stopped at frame {}: {}", log.size(), e.what());
    return Conclude(pipeline, log, n, total.ElapsedMs(), true, args.report);
  }
  return Conclude(pipeline, log, n, total.ElapsedMs(), false, args.report);
}

RunFn Setup(CLI::App& app) {
  auto args = std::make_shared<RunArgs>();
  app.add_option("--settings", args->settings_path, "Settings file (ORB-SLAM2 YAML keys)")->required();
  app.add_option("--sequence", args->flags.run.sequence_dir, "Sequence folder in TUM RGB-D layout")->required();
  app.add_option("--out", args->flags.run.out_dir, "Output folder (created if missing)")->required();
  app.add_option("--max-frames", args->flags.run.max_frames, "Process at most N frames (0 = all)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_flag("--single-thread", args->flags.single_thread,
               "Run local mapping on the tracking thread (deterministic, repeatable)");
  app.add_option("--seed", args->flags.seed, "Seed for random choices")->capture_default_str();
  app.add_flag("--no-relocalization", args->flags.no_relocalization,
               "Disable BoW relocalization when tracking is LOST (same as Loop.relocalization: 0)");
  app.add_flag("--no-loop", args->flags.no_loop, "Disable loop closing (same as Loop.closing: 0), e.g. for the ablation");
  app.add_option("--save-map", args->flags.run.save_map, "Write the final map (keyframes, points) to this binary file");
  auto* load_map = app.add_option("--load-map", args->flags.load_map, "Start from a map saved with --save-map")
                       ->check(CLI::ExistingFile);
  app.add_flag("--localization", args->flags.localization,
               "Localization only: track in the loaded map by relocalization and local-map tracking, "
               "never add keyframes")
      ->needs(load_map);
  app.add_option("--mode", args->mode,
                 "Dynamic-object handling: none (plain ORB-SLAM2 RGB-D) | semantic (segmentation + depth region "
                 "growing masks) | geometry (multi-view geometry check only, no network) | full (both)")
      ->check(CLI::IsMember({"none", "semantic", "geometry", "full"}))
      ->capture_default_str();
  app.add_flag("--realtime", args->flags.realtime,
               "Real-time segmentation hand-off: newest finished labels, carried to the frame by the motion "
               "model and depth (default: wait for every frame's labels)");
  app.add_flag("--dense", args->flags.dense,
               "Build the static dense map of the keyframes: dense.ply, octomap.bt, dense_top.png, "
               "dense_view.png, dense_keyframes.txt and masks/<timestamp>.png in the output folder");
  app.add_option("--debug-frames", args->flags.run.debug_frames_dir,
                 "Write per-frame PNGs to this folder: kept keypoints green, removed by the semantic mask red, "
                 "removed by the geometry check magenta; refined mask tinted cyan, geometry mask magenta");
  app.add_flag("--report", args->report,
               "At the end write OUT/report.html (as `esdslam report`; ground truth from the sequence's "
               "groundtruth.txt)");
  return [args] { return Run(*args); };
}

const Registrar kRegistrar({"run", "Run RGB-D SLAM over a sequence and write the trajectory", Setup, 20});

}  // namespace
}  // namespace esdslam::cli
