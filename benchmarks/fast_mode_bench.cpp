// The cost of the dynamic pipeline (issue 12): the same sequence in `--mode none` and in the
// fast configuration (mode full, labels every K-th frame, predicted masks between), back to back
// in one process, alternating (none, fast), (fast, none), ... so that a noisy shared machine
// loads both alike. Frames are decoded into memory first (as a camera delivers them), so that the
// figures are the pipeline's, not the PNG decoder's; --from-disk reads the folder as esdslam run
// does (decoded ahead on a loader thread, which shares the 2 cores).
//
// Prints, per run and as medians over the runs of each configuration: wall time per frame, CPU
// time per frame of the process and of the tracking thread (the rest is the mask thread's, the
// network's, local mapping's and loop closing's), the per-frame stage times of timing.csv (wall, and CPU
// where the column has it), the time tracking waited for labels, frames without a pose, ATE
// (when the sequence has groundtruth.txt); and the ratio of the median wall times, fast / none.
//
//   build/benchmarks/fast_mode_bench --settings config/bonn.yaml --sequence ../shared/data/bonn_crowd_dev
//   build/esdslam synth --preset dynamic --out /tmp/synth_dyn
//   build/benchmarks/fast_mode_bench --settings /tmp/synth_dyn/settings.yaml --sequence /tmp/synth_dyn
// Options: --pairs N (3), --segment-every K (the settings' Semantic.segmentEvery), --single-thread,
// --from-disk, --max-frames N, --fast-args "every frame" (--segment-every 1: the every-frame
// configuration against none instead).
#include <algorithm>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <opencv2/core/utility.hpp>
#include <spdlog/spdlog.h>

#include "common/timer.h"
#include "eval/ate.h"
#include "io/memory_frame_source.h"
#include "io/prefetching_source.h"
#include "io/trajectory_io.h"
#include "io/tum_sequence.h"
#include "system/frame_columns.h"
#include "system/pipeline.h"
#include "system/run_loop.h"

namespace esdslam {
namespace {


double ProcessCpuMs() {
  timespec now;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now);
  return 1e3 * static_cast<double>(now.tv_sec) + 1e-6 * static_cast<double>(now.tv_nsec);
}

struct Measured {
  double wall_ms = 0, process_cpu_ms = 0, tracking_cpu_ms = 0;  // per frame
  double network_calls = 0;                                    // network runs per frame
  std::map<std::string, double> column_means;                  // timing.csv columns, mean per frame
  int frames = 0, lost = 0;
  double ate_m = -1;  // RMSE; -1 without ground truth
};

struct BenchInput {
  RunSettings settings;
  std::vector<FrameEntry> entries;
  std::vector<RgbdFrame> frames;  // empty with --from-disk
  std::vector<StampedPose> groundtruth;
};

Measured RunOnce(const BenchInput& input, const RunFlags& flags) {
  cv::setNumThreads(-1);  // OpenCV's default: the fast configuration's segmenter sets it process-wide
  const RunConfig config = ResolveRunConfig(input.settings, flags);
  Pipeline pipeline(config);
  std::unique_ptr<FrameSource> source;
  if (input.frames.empty())  // as esdslam run reads a folder: PNGs decoded ahead on a loader thread
    source = std::make_unique<PrefetchingFrameSource>(
        std::make_unique<TumFolderSource>(input.entries, config.settings.core.depth_map_factor));
  else source = std::make_unique<MemoryFrameSource>(input.frames);
  std::vector<double> sums(FrameColumns().size(), 0.0);
  Measured m;
  const double cpu_start = ProcessCpuMs();
  Stopwatch wall;
  ThreadCpuStopwatch tracking_cpu;
  RunFrames(*source, pipeline, [&](const FrameReport& report) {
    const std::vector<double> values = ReadFrameColumns(report);
    for (std::size_t i = 0; i < values.size(); ++i) sums[i] += values[i];
    ++m.frames;
    m.lost += report.track.has_pose ? 0 : 1;
  });
  const double tracking_ms = tracking_cpu.ElapsedMs();
  const double wall_ms = wall.ElapsedMs();
  pipeline.StopSlam();
  const double process_ms = ProcessCpuMs() - cpu_start;
  const double n = std::max(1, m.frames);
  m.wall_ms = wall_ms / n;
  m.process_cpu_ms = process_ms / n;
  m.tracking_cpu_ms = tracking_ms / n;
  if (pipeline.semantic()) m.network_calls = static_cast<double>(pipeline.semantic()->Stats().processed) / n;
  for (std::size_t i = 0; i < sums.size(); ++i) m.column_means[FrameColumns()[i].name] = sums[i] / n;
  if (!input.groundtruth.empty()) m.ate_m = ComputeAte(input.groundtruth, pipeline.system().Trajectory()).translation_m.rmse;
  return m;
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : (v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]));
}

const char* kStageColumns[] = {"load_ms",   "extract_ms",     "track_ms",  "mask_ms",         "predict_ms",
                               "predict_cpu_ms", "grow_ms",   "grow_cpu_ms", "geometry_ms", "geometry_cpu_ms",
                               "seg_wait_ms", "label_age"};

void PrintRun(const std::string& name, const Measured& m) {
  std::printf("%-5s wall %6.2f ms/frame  cpu: process %6.2f, tracking thread %6.2f, other threads %6.2f ms/frame  "
              "network %.3f runs/frame  lost %d/%d  ATE %.4f m\n",
              name.c_str(), m.wall_ms, m.process_cpu_ms, m.tracking_cpu_ms, m.process_cpu_ms - m.tracking_cpu_ms,
              m.network_calls, m.lost, m.frames, m.ate_m);
  std::fflush(stdout);
}

// Median per configuration of every figure, then the stage table and the ratio.
void PrintSummary(const std::map<std::string, std::vector<Measured>>& runs) {
  std::printf("\nmedians over %zu runs each (ms per frame; *_cpu = CPU time of the thread that ran the stage)\n",
              runs.begin()->second.size());
  std::printf("%-22s", "figure");
  for (const auto& [name, list] : runs) std::printf(" %10s", name.c_str());
  std::printf("\n");
  const auto row = [&](const std::string& label, auto get) {
    std::printf("%-22s", label.c_str());
    for (const auto& [name, list] : runs) {
      std::vector<double> values;
      for (const Measured& m : list) values.push_back(get(m));
      std::printf(" %10.3f", Median(values));
    }
    std::printf("\n");
  };
  row("wall", [](const Measured& m) { return m.wall_ms; });
  row("cpu process", [](const Measured& m) { return m.process_cpu_ms; });
  row("cpu tracking thread", [](const Measured& m) { return m.tracking_cpu_ms; });
  row("cpu other threads", [](const Measured& m) { return m.process_cpu_ms - m.tracking_cpu_ms; });
  row("network runs/frame", [](const Measured& m) { return m.network_calls; });
  for (const char* column : kStageColumns)
    row(column, [column](const Measured& m) { return m.column_means.at(column); });
  row("frames lost", [](const Measured& m) { return static_cast<double>(m.lost); });
  row("ATE (m)", [](const Measured& m) { return m.ate_m; });
  std::vector<double> none, fast;
  for (const Measured& m : runs.at("none")) none.push_back(m.wall_ms);
  for (const Measured& m : runs.at("fast")) fast.push_back(m.wall_ms);
  std::vector<double> none_cpu, fast_cpu;
  for (const Measured& m : runs.at("none")) none_cpu.push_back(m.process_cpu_ms);
  for (const Measured& m : runs.at("fast")) fast_cpu.push_back(m.process_cpu_ms);
  std::printf("\nratio fast / none: wall %.3f, process CPU %.3f\n", Median(fast) / Median(none),
              Median(fast_cpu) / Median(none_cpu));
}

BenchInput LoadInput(const std::string& settings_path, const std::string& sequence_dir, int max_frames,
                     bool from_disk) {
  BenchInput input;
  input.settings = LoadRunSettings(settings_path);
  const TumSequence sequence = TumSequence::Open(sequence_dir);
  input.entries = sequence.frames();
  if (max_frames > 0 && static_cast<int>(input.entries.size()) > max_frames) input.entries.resize(max_frames);
  if (std::filesystem::exists(sequence.groundtruth_path())) input.groundtruth = ReadTumTrajectory(sequence.groundtruth_path());
  if (from_disk) return input;
  TumFolderSource source(input.entries, input.settings.core.depth_map_factor);
  while (std::optional<RgbdFrame> frame = source.Next()) input.frames.push_back(std::move(*frame));
  return input;
}

int Main(int argc, char** argv) {
  CLI::App app("fast configuration against --mode none, back to back");
  std::string settings_path, sequence_dir;
  int pairs = 3, segment_every = 0, max_frames = 0;
  bool single_thread = false, from_disk = false;
  app.add_option("--settings", settings_path)->required();
  app.add_option("--sequence", sequence_dir)->required();
  app.add_option("--pairs", pairs)->check(CLI::Range(1, 50));
  app.add_option("--segment-every", segment_every, "K of the fast configuration (0 = the settings')")->check(CLI::Range(0, 1000));
  app.add_option("--max-frames", max_frames)->check(CLI::NonNegativeNumber);
  app.add_flag("--single-thread", single_thread);
  app.add_flag("--from-disk", from_disk, "decode the PNGs during the run on a loader thread, as esdslam run does");
  CLI11_PARSE(app, argc, argv);
  spdlog::set_level(spdlog::level::warn);
  const BenchInput input = LoadInput(settings_path, sequence_dir, max_frames, from_disk);
  RunFlags none, fast;
  none.mode = DynamicMode::kNone;
  fast.mode = DynamicMode::kFull;
  fast.segment_every = segment_every;
  none.single_thread = fast.single_thread = single_thread;
  const RunConfig fast_config = ResolveRunConfig(input.settings, fast);
  std::printf("%zu frames of %s; fast: mode full, segment every %d, label delay %d, model %s, %d OpenCV thread(s) for it\n",
              input.entries.size(), sequence_dir.c_str(), fast_config.settings.semantic.segment_every,
              fast_config.settings.semantic.label_delay_frames, fast_config.settings.semantic.onnx.model_path.c_str(),
              fast_config.settings.semantic.onnx.threads);
  std::map<std::string, std::vector<Measured>> runs;
  for (int pair = 0; pair < pairs; ++pair) {
    const bool none_first = pair % 2 == 0;
    for (int k = 0; k < 2; ++k) {
      const bool is_none = (k == 0) == none_first;
      const std::string name = is_none ? "none" : "fast";
      runs[name].push_back(RunOnce(input, is_none ? none : fast));
      PrintRun(name, runs[name].back());
    }
  }
  PrintSummary(runs);
  return 0;
}

}  // namespace
}  // namespace esdslam

int main(int argc, char** argv) {
  try {
    return esdslam::Main(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fast_mode_bench: %s\n", e.what());
    return 1;
  }
}
