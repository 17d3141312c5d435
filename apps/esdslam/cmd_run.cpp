// `esdslam run --settings FILE (--sequence DIR [--live] | --camera [URI]) --out DIR [--mode ...]`: runs the SLAM
// system over a TUM-layout RGB-D sequence (or a camera, apps/esdslam/run_source.h) and writes
// trajectory.txt, keyframes.txt, timing.csv and settings_used.yaml (every stage's keys); with
// --dense also the dense map. trajectory.txt, keyframes.txt and timing.csv grow frame by frame
// (system/live_outputs.h); SIGINT/SIGTERM stop the run after the current frame with every output
// written (stop_signals.h). The settings file and
// the flags are resolved here, once, into the run's configuration (system/run_config.h); the
// frames go through the pipeline by the run loop (system/run_loop.h). --viewer [PORT] serves the
// live viewer (viewer/live_viewer.h), fed from the run loop's frame callback.
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include <spdlog/spdlog.h>

#include "apps/esdslam/commands.h"
#include "apps/esdslam/run_source.h"
#include "apps/esdslam/stop_signals.h"
#include "common/error.h"
#include "common/timer.h"
#include "io/frame_source.h"
#include "report/run_report.h"
#include "system/frame_log.h"
#include "system/init_diagnosis.h"
#include "system/live_outputs.h"
#include "system/pipeline.h"
#include "system/run_config.h"
#include "system/run_loop.h"
#include "system/run_outputs.h"
#include "system/run_settings.h"
#include "viewer/live_viewer.h"

namespace esdslam::cli {
namespace {

struct RunArgs {
  std::string settings_path;
  std::string mode = "full";
  RunFlags flags;
  bool report = false;  // --report: OUT/report.html at the end (report/run_report.h)
  CameraArgs camera;
  bool viewer = false;       // --viewer given
  std::string viewer_port;   // --viewer's value; empty = the default port
  ViewerOptions viewer_options;
  bool viewer_keep = false;  // --viewer-keep: serve the final state after the run until a signal
};

// The progress line on stderr: redrawn in place every 10 frames on a terminal; into a file or a
// pipe a plain line every few seconds (no carriage returns), and the last frame's line.
class Progress {
 public:
  explicit Progress(std::size_t total) : total_(total), terminal_(::isatty(STDERR_FILENO) != 0) {}
  // done: frames of the input behind us (processed and dropped); total_ 0 = unknown (a camera).
  void Show(const FrameReport& report, std::size_t done, const SlamSystem& system, double elapsed_ms) {
    const bool last = done == total_;
    if (terminal_ ? (done % 10 != 0 && !last) : (elapsed_ms < next_line_ms_ && !last)) return;
    next_line_ms_ = elapsed_ms + kPlainLineIntervalMs;
    const std::string of = total_ > 0 ? "/" + std::to_string(total_) : "";
    std::fprintf(stderr, "%sframe %zu%s  %.1f fps  %-15s  keyframes %d  map points %d%s", terminal_ ? "\r" : "",
                 done, of.c_str(), 1000.0 * static_cast<double>(report.index + 1) / std::max(1.0, elapsed_ms),
                 ToString(report.track.state), system.num_keyframes(), system.num_map_points(),
                 terminal_ ? (last ? "   \n" : "   ") : "\n");
    pending_newline_ = terminal_ && !last;
  }
  // Ends a line redrawn in place before a log line is printed.
  void Break() {
    if (pending_newline_) std::fprintf(stderr, "\n");
    pending_newline_ = false;
  }

 private:
  static constexpr double kPlainLineIntervalMs = 5000;
  std::size_t total_;
  bool terminal_;
  double next_line_ms_ = kPlainLineIntervalMs;
  bool pending_newline_ = false;
};

// OUT/report.html, with the sequence's ground truth when it has one (groundtruth_path, else "").
void WriteReport(const RunConfig& config, const std::string& groundtruth_path, const std::string& summary) {
  ReportOptions options;
  options.out_dir = config.run.out_dir;
  options.groundtruth_path = groundtruth_path;
  options.debug_frames_dir = config.run.debug_frames_dir;
  options.run_summary = summary;
  spdlog::info("run: report {}", WriteRunReport(options));
}

struct RunEnd {
  bool failed = false;   // a stage, the source or an output failed
  int stop_signal = 0;   // stopped by this signal (SIGINT, SIGTERM), 0 = not
};

// Writes every result and prints the summary; returns the exit status: 0, 1 on a failure or a
// map that never initialised, 128 + signal when stopped by one.
int Conclude(Pipeline& pipeline, LiveOutputs& live, const FrameLog& log, const InitDiagnosis& init,
             const RunSource& input, double loop_ms, RunEnd end, bool report) {
  const RunConfig& config = pipeline.config();
  try {
    WriteRunResults(pipeline, live, config.run.out_dir);
  } catch (const std::exception&) {
    end.failed = true;  // (logged by WriteRunResults)
  }
  const std::string summary = FormatRunSummary(log, input.total_frames, pipeline.system(), loop_ms, input.frames_skipped());
  std::fputs(summary.c_str(), stdout);
  std::fflush(stdout);
  if (report) {
    try {
      WriteReport(config, input.groundtruth_path, summary);
    } catch (const std::exception& e) {
      spdlog::error("run: report: {}", e.what());
      end.failed = true;
    }
  }
  const std::string reason = init.Reason(config.slam.tracker.min_initial_depth_keypoints);
  if (!reason.empty()) spdlog::error("run: {}", reason);
  if (end.stop_signal == 0) end.stop_signal = StopSignal();  // a signal while writing
  if (end.stop_signal != 0) {
    spdlog::warn("run: stopped by signal {} after {} frames; every output is written", end.stop_signal, log.size());
    return 128 + end.stop_signal;
  }
  return end.failed || !reason.empty() ? 1 : 0;
}

// The final poses and map to the page; with keep, serves them until SIGINT/SIGTERM.
void FinishViewer(LiveViewer& viewer, bool keep) {
  try {
    viewer.Finish();
  } catch (const std::exception& e) {
    spdlog::error("run: viewer: {}", e.what());
    return;
  }
  if (!keep) return;
  spdlog::info("run: finished; the viewer serves the result at {} until Ctrl-C", viewer.url());
  WaitForStopSignal();
}

// --viewer [PORT] and its options; returns --viewer (given when its count is > 0).
CLI::Option* AddViewerOptions(CLI::App& app, RunArgs& args) {
  CLI::Option* viewer = app.add_option("--viewer", args.viewer_port,
                                       "Serve the live viewer on http://127.0.0.1:PORT/ (default 8080; 0 = any "
                                       "free port, logged)")
                            ->expected(0, 1)
                            ->check(CLI::Range(0, 65535));
  app.add_option("--viewer-address", args.viewer_options.address, "With --viewer: the address to listen on")
      ->capture_default_str()
      ->needs(viewer);
  app.add_flag("--viewer-keep", args.viewer_keep,
               "With --viewer: after the run, keep serving its final state until Ctrl-C")
      ->needs(viewer);
  return viewer;
}

int Run(RunArgs args) {
  RunSettings settings = LoadRunSettings(args.settings_path);
  args.flags.mode = ParseDynamicMode(args.mode);
  if (!args.camera.use && args.flags.run.sequence_dir.empty()) throw Error("run: give --sequence DIR or --camera [URI]");
  // Before the configuration: a camera may bring its own camera model. A bad input fails before OUT is made.
  RunSource input = OpenRunSource(args.flags.run, args.camera, settings.max_consecutive_bad_frames, &settings.core);
  const RunConfig config = ResolveRunConfig(std::move(settings), args.flags);
  const std::size_t n = input.total_frames;
  std::filesystem::create_directories(config.run.out_dir);
  LogRunConfig(config);
  InstallStopSignals();
  Pipeline pipeline(config);
  LiveOutputs live(config.run.out_dir);
  const std::string& debug_dir = config.run.debug_frames_dir;
  if (!debug_dir.empty()) std::filesystem::create_directories(debug_dir);
  std::unique_ptr<LiveViewer> viewer;  // after the pipeline: closed before the system goes
  if (args.viewer) viewer = std::make_unique<LiveViewer>(args.viewer_options, &pipeline.system(), pipeline.dense());
  FrameLog log;
  InitDiagnosis init;
  Progress progress(n);
  Stopwatch total;
  std::size_t done = 0;  // input frames processed or dropped
  RunEnd end;
  try {
    const bool stopped = RunFrames(
        *input.source, pipeline,
        [&](const FrameReport& report) {
          log.Add(report);
          init.Add(report);
          live.Add(report, log.row(log.size() - 1));
          if (!debug_dir.empty()) WriteDebugFrame(debug_dir, report);
          done += 1 + static_cast<std::size_t>(report.dropped_before);
          progress.Show(report, done, pipeline.system(), total.ElapsedMs());
          if (viewer) viewer->Offer(report);  // copies headers only; encoded on the viewer thread
        },
        [] { return StopSignal() != 0; });
    if (stopped) end.stop_signal = StopSignal();
  } catch (const std::exception& e) {  // esdslam::Error, cv::Exception from a stage, bad_alloc
    progress.Break();
    spdlog::error("run: stopped at frame {}: {}", log.size(), e.what());
    end.failed = true;
  }
  progress.Break();
  const int status = Conclude(pipeline, live, log, init, input, total.ElapsedMs(), end, args.report);
  if (viewer) FinishViewer(*viewer, args.viewer_keep && status == 0);
  return status;
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
  app.add_option("--associations", args->flags.run.associations,
                 "ORB-SLAM2 association file 'ts_rgb rgb/F ts_depth depth/F' (paths relative to the sequence); "
                 "default: rgb.txt and depth.txt, or DIR/associations.txt when those are missing")
      ->check(CLI::ExistingFile);
  app.add_option("--max-frames", args->flags.run.max_frames, "Process at most N frames (0 = all)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_flag("--single-thread", args->flags.single_thread,
               "Run local mapping on the tracking thread (deterministic, repeatable)");
  app.add_option("--seed", args->flags.seed, "Seed of the RANSACs (relocalization PnP, loop verification)")->capture_default_str();
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
  app.add_option("--segment-every", args->flags.segment_every,
                 "The network labels every K-th frame on its own thread (and earlier when a predicted mask is no "
                 "longer trusted); the frames between get the labels carried along the optical flow. 1 = label "
                 "every frame and wait for it. Default: Semantic.segmentEvery (4)")
      ->check(CLI::Range(1, 1000));
  app.add_flag("--realtime", args->flags.realtime,
               "Live input: the network takes the newest frame whenever it is free, its labels are used as soon "
               "as they are back and carried along the optical flow (never waits, not repeatable)");
  app.add_flag("--live", args->flags.run.live,
               "Sensor-clock playback: frames arrive at their timestamps, a frame arriving while the system is "
               "busy is dropped (counted in the summary and timing.csv's dropped_before)");
  app.add_flag("--dense", args->flags.dense,
               "Build the static dense map of the keyframes: dense.ply, octomap.bt, dense_top.png, "
               "dense_view.png, dense_keyframes.txt and masks/<timestamp>.png in the output folder");
  app.add_option("--debug-frames", args->flags.run.debug_frames_dir,
                 "Write per-frame PNGs to this folder: kept keypoints green, removed by the semantic mask red, "
                 "removed by the geometry check magenta; refined mask tinted cyan, geometry mask magenta");
  app.add_flag("--report", args->report,
               "At the end write OUT/report.html (as `esdslam report`; ground truth from the sequence's "
               "groundtruth.txt)");
  CLI::Option* viewer = AddViewerOptions(app, *args);
  return [args, camera, viewer] {
    args->camera.use = camera->count() > 0;
    args->viewer = viewer->count() > 0;
    if (!args->viewer_port.empty()) args->viewer_options.port = std::stoi(args->viewer_port);
    return Run(*args);
  };
}

const Registrar kRegistrar({"run", "Run RGB-D SLAM over a sequence and write the trajectory", Setup, 20});

}  // namespace
}  // namespace esdslam::cli
