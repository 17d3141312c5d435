// `esdslam run --settings FILE (--sequence DIR [--live] | --camera [URI]) --out DIR [--mode ...]`: runs the SLAM
// system over a TUM-layout RGB-D sequence (or a camera, apps/esdslam/run_source.h) and writes
// trajectory.txt, keyframes.txt, timing.csv and settings_used.yaml (every stage's keys); with
// --dense also the dense map. The settings file and
// the flags are resolved here, once, into the run's configuration (system/run_config.h); the
// frames go through the pipeline by the run loop (system/run_loop.h).
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include <spdlog/spdlog.h>

#include "apps/esdslam/commands.h"
#include "apps/esdslam/run_source.h"
#include "common/error.h"
#include "common/timer.h"
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
  CameraArgs camera;
};

// done: frames of the input behind us (processed and dropped).
void ShowProgress(const FrameReport& report, std::size_t done, std::size_t n, const SlamSystem& system,
                  double elapsed_ms) {
  if (report.index % 10 != 9 && done != n) return;
  const std::string of = n > 0 ? "/" + std::to_string(n) : "";  // a camera: no end known
  std::fprintf(stderr, "\rframe %zu%s  %.1f fps  %-15s  keyframes %d  map points %d   ", done, of.c_str(),
               1000.0 * static_cast<double>(report.index + 1) / std::max(1.0, elapsed_ms), ToString(report.track.state),
               system.num_keyframes(), system.num_map_points());
  if (done == n) std::fprintf(stderr, "\n");
}

// Writes every result and prints the summary; returns the exit status.
int Conclude(Pipeline& pipeline, const FrameLog& log, std::size_t total_frames, double loop_ms, bool failed) {
  const RunConfig& config = pipeline.config();
  WriteRunResults(pipeline, log, config.run.out_dir);
  std::fputs(FormatRunSummary(log, total_frames, pipeline.system(), loop_ms).c_str(), stdout);
  if (failed) return 1;
  if (!config.run.save_map.empty()) pipeline.system().SaveMap(config.run.save_map);
  return 0;
}

int Run(RunArgs args) {
  RunSettings settings = LoadRunSettings(args.settings_path);
  args.flags.mode = ParseDynamicMode(args.mode);
  if (!args.camera.use && args.flags.run.sequence_dir.empty()) throw Error("run: give --sequence DIR or --camera [URI]");
  // Before the configuration: a camera may bring its own camera model. A bad input fails before OUT is made.
  RunSource input = OpenRunSource(args.flags.run, args.camera, &settings.core);
  const RunConfig config = ResolveRunConfig(std::move(settings), args.flags);
  const std::size_t n = input.total_frames;
  std::filesystem::create_directories(config.run.out_dir);
  LogRunConfig(config);
  Pipeline pipeline(config);
  const std::string& debug_dir = config.run.debug_frames_dir;
  if (!debug_dir.empty()) std::filesystem::create_directories(debug_dir);
  FrameLog log;
  Stopwatch total;
  std::size_t done = 0;  // input frames processed or dropped
  try {
    RunFrames(*input.source, pipeline, [&](const FrameReport& report) {
      if (!debug_dir.empty()) WriteDebugFrame(debug_dir, report);
      log.Add(report);
      done += 1 + static_cast<std::size_t>(report.dropped_before);
      ShowProgress(report, done, n, pipeline.system(), total.ElapsedMs());
    });
  } catch (const Error& e) {
    std::fprintf(stderr, "\n");
    spdlog::error("run: stopped at frame {}: {}", log.size(), e.what());
    return Conclude(pipeline, log, n, total.ElapsedMs(), true);
  }
  return Conclude(pipeline, log, n, total.ElapsedMs(), false);
}

// --camera and its options; returns --camera (given when its count is > 0).
CLI::Option* AddCameraOptions(CLI::App& app, CameraArgs& camera_args, CLI::Option* sequence) {
  CLI::Option* camera = app.add_option("--camera", camera_args.uri,
                                "Instead of --sequence: an OpenNI2 camera (URI; none = the first attached) or an "
                                ".oni recording")
                     ->expected(0, 1)
                     ->excludes(sequence);
  app.add_option("--camera-model", camera_args.model_from,
                 "With --camera: camera model from the device (field of view) or the settings file (calibrated)")
      ->check(CLI::IsMember({"device", "settings"}))
      ->capture_default_str()
      ->needs(camera);
  app.add_option("--camera-registration", camera_args.registration,
                 "With --camera: depth registered to colour by the device (software when it cannot), or off")
      ->check(CLI::IsMember({"device", "off"}))
      ->capture_default_str()
      ->needs(camera);
  return camera;
}

RunFn Setup(CLI::App& app) {
  auto args = std::make_shared<RunArgs>();
  app.add_option("--settings", args->settings_path, "Settings file (ORB-SLAM2 YAML keys)")->required();
  auto* sequence = app.add_option("--sequence", args->flags.run.sequence_dir, "Sequence folder in TUM RGB-D layout");
  CLI::Option* camera = AddCameraOptions(app, args->camera, sequence);
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
  app.add_flag("--live", args->flags.run.live,
               "Sensor-clock playback: frames arrive at their timestamps, a frame arriving while the system is "
               "busy is dropped (counted in the summary and timing.csv's dropped_before)");
  app.add_flag("--dense", args->flags.dense,
               "Build the static dense map of the keyframes: dense.ply, octomap.bt, dense_top.png, "
               "dense_view.png, dense_keyframes.txt and masks/<timestamp>.png in the output folder");
  app.add_option("--debug-frames", args->flags.run.debug_frames_dir,
                 "Write per-frame PNGs to this folder: kept keypoints green, removed by the semantic mask red, "
                 "removed by the geometry check magenta; refined mask tinted cyan, geometry mask magenta");
  return [args, camera] {
    args->camera.use = camera->count() > 0;
    return Run(*args);
  };
}

const Registrar kRegistrar({"run", "Run RGB-D SLAM over a sequence and write the trajectory", Setup, 20});

}  // namespace
}  // namespace esdslam::cli
