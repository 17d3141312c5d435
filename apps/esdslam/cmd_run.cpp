// `esdslam run --settings FILE --sequence DIR --out DIR [--mode none|semantic|geometry|full]`: runs the SLAM
// system over a TUM-layout RGB-D sequence and writes trajectory.txt, keyframes.txt, timing.csv and
// settings_used.yaml (every stage's keys); with --dense also the dense map (system/dynamic_run.h).
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>

#include "apps/esdslam/commands.h"
#include "common/error.h"
#include "common/timer.h"
#include "io/settings.h"
#include "io/trajectory_io.h"
#include "io/tum_sequence.h"
#include "system/dynamic_run.h"
#include "system/run_settings.h"
#include "system/slam_system.h"

namespace esdslam::cli {
namespace {

struct RunArgs {
  std::string settings_path;
  std::string sequence_dir;
  std::string out_dir;
  int max_frames = 0;
  bool single_thread = false;
  unsigned seed = 0;
  std::string mode = "full";
  bool realtime = false;
  bool dense = false;
  std::string debug_frames_dir;
  bool no_relocalization = false;
  bool no_loop = false;
  std::string save_map;
  std::string load_map;
  bool localization = false;
};

struct FrameTiming {
  double timestamp = 0;
  double load_ms = 0, extract_ms = 0, track_ms = 0;
  TrackingState state = TrackingState::kNotInitialized;
  bool has_pose = false;
  // Semantic stage (0 in mode none): segmentation latency of the frame whose labels were used,
  // time tracking waited for them, mask refinement, label age in frames, keypoints flagged.
  double seg_latency_ms = 0, seg_wait_ms = 0, mask_ms = 0;
  long label_age = -1;
  double dynamic_fraction = 0;
  int keypoints = 0, dynamic_keypoints = 0;
  // Region growing alone (part of mask_ms); geometry check (part of track_ms), the keypoints it
  // marked dynamic and the map points it culled.
  double grow_ms = 0, geometry_ms = 0;
  double grow_cpu_ms = 0, geometry_cpu_ms = 0;  // the same as thread CPU time (shared machines)
  int geometry_keypoints = 0, geometry_culled = 0;
  int geometry_covered = 0, geometry_window_px = 0;  // covered reference points; depth window (-1: skipped)
};

void LogSettings(const Settings& s, const RunArgs& args) {
  const auto& c = s.camera;
  spdlog::info("run: sequence {} -> {}", args.sequence_dir, args.out_dir);
  spdlog::info("run: camera fx={} fy={} cx={} cy={} k=[{} {} {} {} {}] {}x{} fps={}", c.fx, c.fy, c.cx, c.cy, c.k1,
               c.k2, c.p1, c.p2, c.k3, c.width, c.height, s.fps);
  spdlog::info("run: bf={} ThDepth={} DepthMapFactor={} RGB={} ORB nFeatures={} scale={} levels={} FAST={}/{}", s.bf,
               s.th_depth, s.depth_map_factor, s.rgb_order, s.orb.num_features, s.orb.scale_factor, s.orb.num_levels,
               s.orb.initial_fast_threshold, s.orb.min_fast_threshold);
  spdlog::info("run: {} seed={}", args.single_thread ? "single-thread" : "two threads", args.seed);
}

void WriteTiming(const std::string& path, const std::vector<FrameTiming>& timings) {
  std::ofstream out(path);
  if (!out) throw Error("cannot write " + path);
  out << "timestamp,load_ms,extract_ms,track_ms,state,lost,seg_latency_ms,seg_wait_ms,mask_ms,label_age,"
         "dynamic_fraction,keypoints,dynamic_keypoints,grow_ms,geometry_ms,geometry_keypoints,geometry_culled,"
         "geometry_covered,geometry_window_px,grow_cpu_ms,geometry_cpu_ms\n";
  for (const FrameTiming& t : timings)
    out << fmt::format("{:.6f},{:.3f},{:.3f},{:.3f},{},{},{:.3f},{:.3f},{:.3f},{},{:.4f},{},{},{:.3f},{:.3f},{},{},{},{},{:.3f},"
                       "{:.3f}\n",
                       t.timestamp, t.load_ms, t.extract_ms, t.track_ms, ToString(t.state), t.has_pose ? 0 : 1,
                       t.seg_latency_ms, t.seg_wait_ms, t.mask_ms, t.label_age, t.dynamic_fraction, t.keypoints,
                       t.dynamic_keypoints, t.grow_ms, t.geometry_ms, t.geometry_keypoints, t.geometry_culled,
                       t.geometry_covered, t.geometry_window_px, t.grow_cpu_ms, t.geometry_cpu_ms);
}

struct StageStats {
  double mean = 0, median = 0;
};
StageStats Stats(std::vector<double> values) {
  if (values.empty()) return {};
  StageStats s;
  for (double v : values) s.mean += v / values.size();
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  s.median = values[values.size() / 2];
  return s;
}

// elapsed_ms: wall time of the frame loop (loading, segmentation hand-off, tracking).
void PrintSummary(const std::vector<FrameTiming>& timings, int total_frames, const SlamSystem& system,
                  double elapsed_ms) {
  std::vector<double> load, extract, track, seg_latency, seg_wait, mask, grow, geometry, dynamic, dynamic_cpu;
  int tracked = 0;
  long culled = 0;
  for (const FrameTiming& t : timings) {
    load.push_back(t.load_ms), extract.push_back(t.extract_ms), track.push_back(t.track_ms);
    seg_latency.push_back(t.seg_latency_ms), seg_wait.push_back(t.seg_wait_ms), mask.push_back(t.mask_ms);
    grow.push_back(t.grow_ms), geometry.push_back(t.geometry_ms), dynamic.push_back(t.grow_ms + t.geometry_ms);
    dynamic_cpu.push_back(t.grow_cpu_ms + t.geometry_cpu_ms);
    tracked += t.has_pose;
    culled += t.geometry_culled;
  }
  const auto print = [](const char* name, const StageStats& s) {
    std::printf("%-8s mean %7.2f ms  median %7.2f ms\n", name, s.mean, s.median);
  };
  print("load", Stats(load));
  print("extract", Stats(extract));
  print("track", Stats(track));
  print("seg_lat", Stats(seg_latency));
  print("seg_wait", Stats(seg_wait));
  print("mask", Stats(mask));
  print("grow", Stats(grow));
  print("geometry", Stats(geometry));
  print("grow+geo", Stats(dynamic));
  print("(cpu)", Stats(dynamic_cpu));
  std::printf("frames_tracked %d / %d (processed %zu)\n", tracked, total_frames, timings.size());
  std::printf("fps %.1f (frames processed per second of wall time)\n",
              1000.0 * static_cast<double>(timings.size()) / std::max(1.0, elapsed_ms));
  std::printf("points_culled_by_geometry %ld\n", culled);
  std::printf("keyframes %d\nmap_points %d\n", system.num_keyframes(), system.num_map_points());
  std::printf("relocalizations %d\n", system.relocalizations());
  const LoopClosingStats loops = system.loop_stats();
  std::printf("loops_closed %d (keyframes checked %d, candidates verified %d, global BA %d done / %d aborted)\n",
              loops.loops_closed, loops.keyframes_checked, loops.consistent_candidates, loops.global_ba.completed,
              loops.global_ba.aborted);
  if (loops.keyframes_checked > 0)
    std::printf("loop_timing detection %.2f ms/keyframe, verification %.2f ms/candidate, global BA %.0f ms/run\n",
                loops.detect_ms / loops.keyframes_checked,
                loops.consistent_candidates > 0 ? loops.verify_ms / loops.consistent_candidates : 0.0,
                loops.global_ba.completed > 0 ? loops.global_ba.total_ms / loops.global_ba.completed : 0.0);
  for (const LoopEvent& event : loops.events)
    std::printf("loop keyframe %ld -> %ld at t=%.3f: %d inliers, %d matches, correction %.3f m %.2f deg, %.0f ms\n",
                event.current_id, event.loop_id, event.timestamp, event.inliers, event.matches, event.correction_m,
                event.correction_deg, event.correct_ms);
}

void WriteResults(const RunArgs& args, DynamicRun& run, const RunSettings& settings,
                  const std::vector<FrameTiming>& timings) {
  SlamSystem& system = run.system();
  std::string shutdown_error;  // results are written even when local mapping failed
  try {
    run.Finish(args.out_dir);
  } catch (const Error& e) {
    shutdown_error = e.what();
  }
  const std::filesystem::path out(args.out_dir);
  WriteTumTrajectory((out / "trajectory.txt").string(), system.Trajectory());
  WriteTumTrajectory((out / "keyframes.txt").string(), system.KeyFrameTrajectory());
  WriteTiming((out / "timing.csv").string(), timings);
  SaveRunSettings(settings, (out / "settings_used.yaml").string());
  if (!shutdown_error.empty()) throw Error(shutdown_error);
}

void ShowProgress(std::size_t i, std::size_t n, const FrameTiming& t, const SlamSystem& system, double elapsed_ms) {
  std::fprintf(stderr, "\rframe %zu/%zu  %.1f fps  %-15s  keyframes %d  map points %d   ", i + 1, n,
               1000.0 * (i + 1) / std::max(1.0, elapsed_ms), ToString(t.state), system.num_keyframes(),
               system.num_map_points());
  if (i + 1 == n) std::fprintf(stderr, "\n");
}

// One line per effective settings key (all stages), after the command-line overrides.
void LogEffectiveSettings(const RunSettings& settings, const DynamicRunOptions& options) {
  spdlog::info("run: mode {}, segmentation {}, dense {}, debug frames {}", ToString(options.mode),
               options.realtime ? "real time (newest wins)" : "every frame", options.dense ? "on" : "off",
               options.debug_frames_dir.empty() ? "off" : options.debug_frames_dir);
  std::istringstream lines(RunSettingsYaml(settings));
  std::string line;
  while (std::getline(lines, line)) {
    if (line.rfind("%YAML", 0) != 0) spdlog::info("settings: {}", line);
  }
}

void CopyStep(const FrameStep& step, FrameTiming& t) {
  t.load_ms = step.load_ms;
  t.extract_ms = step.outcome.extract_ms, t.track_ms = step.outcome.track_ms;
  t.state = step.outcome.state, t.has_pose = step.outcome.has_pose;
  t.seg_latency_ms = step.mask.latency_ms, t.seg_wait_ms = step.mask.wait_ms, t.mask_ms = step.mask.refine_ms;
  t.dynamic_fraction = step.mask.dynamic_fraction;
  t.keypoints = step.keypoints, t.dynamic_keypoints = step.dynamic_keypoints;
  const GeometryFilterStats& geometry = step.outcome.geometry;
  t.grow_ms = step.mask.grow_ms, t.geometry_ms = geometry.check_ms;
  t.geometry_keypoints = step.geometry_keypoints, t.geometry_culled = geometry.points_culled;
  t.geometry_covered = geometry.covered, t.geometry_window_px = geometry.skipped_fast_motion ? -1 : geometry.window_radius_px;
  t.grow_cpu_ms = step.mask.grow_cpu_ms, t.geometry_cpu_ms = geometry.check_cpu_ms;
}

int Run(const RunArgs& args) {
  RunSettings run_settings = LoadRunSettings(args.settings_path);
  const Settings& settings = run_settings.core;
  const TumSequence sequence = TumSequence::Open(args.sequence_dir);
  std::filesystem::create_directories(args.out_dir);
  LogSettings(settings, args);
  SlamOptions options;
  options.single_thread = args.single_thread;
  options.seed = args.seed;
  if (args.no_relocalization) run_settings.loop.relocalization = false;
  if (args.no_loop) run_settings.loop.closing = false;
  options.loop = run_settings.loop;
  options.load_map = args.load_map;
  options.tracker.localization_only = args.localization;
  DynamicRunOptions run_options;
  run_options.mode = ParseDynamicMode(args.mode);
  run_options.realtime = args.realtime || run_settings.semantic.mode == SegmentationMode::kNewestWins;
  if (run_options.realtime) run_settings.semantic.mode = SegmentationMode::kNewestWins;
  run_options.dense = args.dense;
  if (args.dense) run_options.dense_mask_dir = (std::filesystem::path(args.out_dir) / "masks").string();
  run_options.debug_frames_dir = args.debug_frames_dir;
  run_options.threaded_dense = !args.single_thread;
  LogEffectiveSettings(run_settings, run_options);
  std::size_t n = sequence.frames().size();
  if (args.max_frames > 0) n = std::min<std::size_t>(n, args.max_frames);
  const std::vector<FrameEntry> frames(sequence.frames().begin(), sequence.frames().begin() + n);
  DynamicRun run(run_settings, options, run_options, frames);
  SlamSystem& system = run.system();
  std::vector<FrameTiming> timings;
  Stopwatch total;
  try {
    for (std::size_t i = 0; i < n; ++i) {
      FrameTiming t;
      t.timestamp = frames[i].timestamp;
      const FrameStep step = run.Step(i);
      CopyStep(step, t);
      if (step.mask.source_id >= 0) t.label_age = static_cast<long>(i) - static_cast<long>(step.mask.source_id);
      timings.push_back(t);
      if ((i + 1) % 10 == 0 || i + 1 == n) ShowProgress(i, n, t, system, total.ElapsedMs());
    }
  } catch (const Error& e) {
    std::fprintf(stderr, "\n");
    spdlog::error("run: stopped at frame {}: {}", timings.size(), e.what());
    const double loop_ms = total.ElapsedMs();
    WriteResults(args, run, run_settings, timings);
    PrintSummary(timings, static_cast<int>(n), system, loop_ms);
    return 1;
  }
  const double loop_ms = total.ElapsedMs();
  WriteResults(args, run, run_settings, timings);
  PrintSummary(timings, static_cast<int>(n), system, loop_ms);
  if (!args.save_map.empty()) system.SaveMap(args.save_map);
  return 0;
}

RunFn Setup(CLI::App& app) {
  auto args = std::make_shared<RunArgs>();
  app.add_option("--settings", args->settings_path, "Settings file (ORB-SLAM2 YAML keys)")->required();
  app.add_option("--sequence", args->sequence_dir, "Sequence folder in TUM RGB-D layout")->required();
  app.add_option("--out", args->out_dir, "Output folder (created if missing)")->required();
  app.add_option("--max-frames", args->max_frames, "Process at most N frames (0 = all)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_flag("--single-thread", args->single_thread,
               "Run local mapping on the tracking thread (deterministic, repeatable)");
  app.add_option("--seed", args->seed, "Seed for random choices")->capture_default_str();
  app.add_flag("--no-relocalization", args->no_relocalization,
               "Disable BoW relocalization when tracking is LOST (same as Loop.relocalization: 0)");
  app.add_flag("--no-loop", args->no_loop, "Disable loop closing (same as Loop.closing: 0), e.g. for the ablation");
  app.add_option("--save-map", args->save_map, "Write the final map (keyframes, points) to this binary file");
  auto* load_map = app.add_option("--load-map", args->load_map, "Start from a map saved with --save-map")
                       ->check(CLI::ExistingFile);
  app.add_flag("--localization", args->localization,
               "Localization only: track in the loaded map by relocalization and local-map tracking, "
               "never add keyframes")
      ->needs(load_map);
  app.add_option("--mode", args->mode,
                 "Dynamic-object handling: none (plain ORB-SLAM2 RGB-D) | semantic (segmentation + depth region "
                 "growing masks) | geometry (multi-view geometry check only, no network) | full (both)")
      ->check(CLI::IsMember({"none", "semantic", "geometry", "full"}))
      ->capture_default_str();
  app.add_flag("--realtime", args->realtime,
               "Real-time segmentation hand-off: newest finished labels, carried to the frame by the motion "
               "model and depth (default: wait for every frame's labels)");
  app.add_flag("--dense", args->dense,
               "Build the static dense map of the keyframes: dense.ply, octomap.bt, dense_top.png, "
               "dense_view.png, dense_keyframes.txt and masks/<timestamp>.png in the output folder");
  app.add_option("--debug-frames", args->debug_frames_dir,
                 "Write per-frame PNGs to this folder: kept keypoints green, removed by the semantic mask red, "
                 "removed by the geometry check magenta; refined mask tinted cyan, geometry mask magenta");
  return [args] { return Run(*args); };
}

const Registrar kRegistrar({"run", "Run RGB-D SLAM over a sequence and write the trajectory", Setup, 20});

}  // namespace
}  // namespace esdslam::cli
