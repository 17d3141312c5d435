// `esdslam run --settings FILE --sequence DIR --out DIR`: runs the SLAM system over a TUM-layout
// RGB-D sequence and writes trajectory.txt, keyframes.txt, timing.csv and settings_used.yaml.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>

#include "apps/esdslam/commands.h"
#include "common/error.h"
#include "common/timer.h"
#include "io/settings.h"
#include "io/trajectory_io.h"
#include "io/tum_sequence.h"
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
};

struct FrameTiming {
  double timestamp = 0;
  double load_ms = 0, extract_ms = 0, track_ms = 0;
  TrackingState state = TrackingState::kNotInitialized;
  bool has_pose = false;
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
  out << "timestamp,load_ms,extract_ms,track_ms,state,lost\n";
  for (const FrameTiming& t : timings)
    out << fmt::format("{:.6f},{:.3f},{:.3f},{:.3f},{},{}\n", t.timestamp, t.load_ms, t.extract_ms, t.track_ms,
                       ToString(t.state), t.has_pose ? 0 : 1);
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

void PrintSummary(const std::vector<FrameTiming>& timings, int total_frames, const SlamSystem& system) {
  std::vector<double> load, extract, track;
  int tracked = 0;
  for (const FrameTiming& t : timings) {
    load.push_back(t.load_ms), extract.push_back(t.extract_ms), track.push_back(t.track_ms);
    tracked += t.has_pose;
  }
  const auto print = [](const char* name, const StageStats& s) {
    std::printf("%-8s mean %7.2f ms  median %7.2f ms\n", name, s.mean, s.median);
  };
  print("load", Stats(load));
  print("extract", Stats(extract));
  print("track", Stats(track));
  std::printf("frames_tracked %d / %d (processed %zu)\n", tracked, total_frames, timings.size());
  std::printf("keyframes %d\nmap_points %d\n", system.num_keyframes(), system.num_map_points());
}

void WriteResults(const RunArgs& args, SlamSystem& system, const Settings& settings,
                  const std::vector<FrameTiming>& timings) {
  system.Shutdown();
  const std::filesystem::path out(args.out_dir);
  WriteTumTrajectory((out / "trajectory.txt").string(), system.Trajectory());
  WriteTumTrajectory((out / "keyframes.txt").string(), system.KeyFrameTrajectory());
  WriteTiming((out / "timing.csv").string(), timings);
  SaveSettings(settings, (out / "settings_used.yaml").string());
}

void ShowProgress(std::size_t i, std::size_t n, const FrameTiming& t, const SlamSystem& system, double elapsed_ms) {
  std::fprintf(stderr, "\rframe %zu/%zu  %.1f fps  %-15s  keyframes %d  map points %d   ", i + 1, n,
               1000.0 * (i + 1) / std::max(1.0, elapsed_ms), ToString(t.state), system.num_keyframes(),
               system.num_map_points());
  if (i + 1 == n) std::fprintf(stderr, "\n");
}

int Run(const RunArgs& args) {
  const Settings settings = LoadSettings(args.settings_path);
  const TumSequence sequence = TumSequence::Open(args.sequence_dir);
  std::filesystem::create_directories(args.out_dir);
  LogSettings(settings, args);
  SlamOptions options;
  options.single_thread = args.single_thread;
  options.seed = args.seed;
  SlamSystem system(settings, options);
  std::size_t n = sequence.frames().size();
  if (args.max_frames > 0) n = std::min<std::size_t>(n, args.max_frames);
  std::vector<FrameTiming> timings;
  Stopwatch total;
  try {
    for (std::size_t i = 0; i < n; ++i) {
      FrameTiming t;
      const FrameEntry& entry = sequence.frames()[i];
      t.timestamp = entry.timestamp;
      Stopwatch load;
      const RgbdImages images = LoadRgbd(entry, settings.depth_map_factor);
      t.load_ms = load.ElapsedMs();
      const TrackOutcome outcome = system.TrackRgbd(images.bgr, images.depth_m, entry.timestamp);
      t.extract_ms = outcome.extract_ms, t.track_ms = outcome.track_ms;
      t.state = outcome.state, t.has_pose = outcome.has_pose;
      timings.push_back(t);
      if ((i + 1) % 10 == 0 || i + 1 == n) ShowProgress(i, n, t, system, total.ElapsedMs());
    }
  } catch (const Error& e) {
    std::fprintf(stderr, "\n");
    spdlog::error("run: stopped at frame {}: {}", timings.size(), e.what());
    WriteResults(args, system, settings, timings);
    PrintSummary(timings, static_cast<int>(n), system);
    return 1;
  }
  WriteResults(args, system, settings, timings);
  PrintSummary(timings, static_cast<int>(n), system);
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
  return [args] { return Run(*args); };
}

const Registrar kRegistrar({"run", "Run RGB-D SLAM over a sequence and write the trajectory", Setup, 20});

}  // namespace
}  // namespace esdslam::cli
