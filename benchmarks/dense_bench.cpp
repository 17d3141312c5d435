// Cost of the static dense map on the dev sequences: time per keyframe on the dense thread
// (back-projection, re-indexing, integration), time of the final build (global cloud with
// outlier removal, OctoMap ray casting), and memory: the map's own structures (counted bytes)
// and the process's peak RSS. Keyframes are the sequence's frames at the ground-truth poses,
// every `step`-th frame (arg), without dynamic masks (people are mapped: an upper bound on the
// map size; people walking through Bonn add new "ghost" geometry with every frame). The same room
// seen by 10x more keyframes must not need 10x the memory: BM_DenseMap_SynthStatic shows it on
// surfaces with known coverage, with and without depth noise.
//
//   build/benchmarks/dense_bench                                   # all cases, one process
//   build/benchmarks/dense_bench --benchmark_filter='Bonn/1/'      # one case: its own peak RSS
//   build/benchmarks/dense_bench --benchmark_filter='Bonn/10/'     # keyframe time without / with free-space consistency
#include <sys/resource.h>

#include <filesystem>
#include <functional>

#include <benchmark/benchmark.h>

#include "common/timer.h"
#include "dense/dense_mapper.h"
#include "io/associate.h"
#include "io/trajectory_io.h"
#include "io/tum_sequence.h"
#include "synth/synthetic_scene.h"
#include "system/run_settings.h"

namespace esdslam {
namespace {

double PeakRssMb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;  // Linux: kilobytes
}

struct Sequence {
  std::string dir;
  RunSettings settings;
  std::vector<FrameEntry> frames;  // frames with a ground-truth pose
  std::vector<Rigid3> world_from_cam;
};

Sequence OpenSequence(const std::string& name, const std::string& config) {
  Sequence seq;
  seq.dir = std::string(ESDSLAM_TEST_DATA_DIR) + "/data/" + name;
  seq.settings = LoadRunSettings(std::string(ESDSLAM_SOURCE_DIR) + "/config/" + config);
  const TumSequence sequence = TumSequence::Open(seq.dir);
  const std::vector<StampedPose> truth = ReadTumTrajectory(seq.dir + "/groundtruth.txt");
  std::vector<double> frame_times, truth_times;
  for (const FrameEntry& f : sequence.frames()) frame_times.push_back(f.timestamp);
  for (const StampedPose& p : truth) truth_times.push_back(p.timestamp);
  for (const TimestampMatch& m : AssociateTimestamps(frame_times, truth_times, 0.02)) {
    seq.frames.push_back(sequence.frames()[m.first]);
    seq.world_from_cam.push_back(truth[m.second].world_from_cam);
  }
  return seq;
}

// Maps every `step`-th (arg 0) of `frames` keyframes, `load(i)` giving keyframe i (not timed),
// then writes the outputs (no pictures) and reports the counters.
void MapAndReport(benchmark::State& state, const PinholeCamera& camera, const DenseOptions& options, std::size_t frames,
                  const std::function<DenseKeyframe(std::size_t)>& load) {
  const auto step = static_cast<std::size_t>(state.range(0));
  const std::string out = (std::filesystem::temp_directory_path() / "esdslam_dense_bench").string();
  DenseMapperStats stats;
  DenseOutputSummary summary;
  for (auto _ : state) {
    DenseMapperOptions mapper;
    mapper.threaded = false;  // time each keyframe alone
    DenseMapper dense(camera, options, {}, mapper);
    for (std::size_t i = 0; i < frames; i += step) {
      state.PauseTiming();
      DenseKeyframe keyframe = load(i);
      state.ResumeTiming();
      dense.AddKeyframe(std::move(keyframe));
    }
    DenseOutputFiles files;
    files.pictures = false;
    summary = dense.WriteOutputs(out, files);
    stats = dense.stats();
  }
  state.counters["keyframes"] = static_cast<double>(stats.keyframes);
  state.counters["keyframe_ms"] = stats.mean_keyframe_ms;
  state.counters["keyframe_max_ms"] = stats.max_keyframe_ms;
  state.counters["keyframe_cpu_ms"] = stats.mean_keyframe_cpu_ms;
  state.counters["final_cloud_ms"] = summary.cloud_ms;
  state.counters["final_octomap_ms"] = summary.octomap_ms;
  state.counters["stored_points"] = static_cast<double>(stats.map.points);
  state.counters["carved_points"] = static_cast<double>(stats.map.carved_points);
  state.counters["output_points"] = static_cast<double>(summary.points);
  state.counters["map_MB"] = stats.map.point_bytes / 1e6;
  state.counters["rays_MB"] = stats.map.ray_bytes / 1e6;
  state.counters["octomap_occupied"] = static_cast<double>(summary.occupied_leaves);
  state.counters["peak_rss_MB"] = PeakRssMb();
}

// Arg 1 = 0: without the free-space consistency and the depth-edge filter (the map before
// issue 18), 1: with them (default settings); run back to back in one process for the ratio.
DenseOptions WithConsistency(DenseOptions options, std::int64_t on) {
  if (on == 0) {
    options.free_space_carving = false;
    options.edge_filter_px = 0;
  }
  return options;
}

void MapSequence(benchmark::State& state, const std::string& name, const std::string& config) {
  if (!std::filesystem::exists(std::string(ESDSLAM_TEST_DATA_DIR) + "/data/" + name)) {
    state.SkipWithError((name + " not found").c_str());
    return;
  }
  const Sequence seq = OpenSequence(name, config);
  const DenseOptions options = WithConsistency(seq.settings.dense, state.range(1));
  MapAndReport(state, PinholeCamera(seq.settings.core.camera), options, seq.frames.size(), [&](std::size_t i) {
    const RgbdImages images = LoadRgbd(seq.frames[i], seq.settings.core.depth_map_factor);
    return DenseKeyframe{static_cast<long>(i), seq.frames[i].timestamp, seq.world_from_cam[i], images.bgr, images.depth_m, cv::Mat()};
  });
}

// The synthetic static room (240 frames along the arc, ground-truth poses, every `step`-th frame),
// with exact depth (arg 1 = 0) or Kinect-like noise sigma = 1.5 mm * z^2 (arg 1 = 15, in 0.1 mm):
// the same surfaces seen by 10x more keyframes; arg 2 as arg 1 of MapSequence.
void BM_DenseMap_SynthStatic(benchmark::State& state) {
  SynthOptions synth = SynthPreset("static");
  synth.depth_noise_at_1m = 1e-4 * static_cast<double>(state.range(1));
  const SyntheticScene scene(synth);
  DenseOptions options = WithConsistency(DenseOptions{}, state.range(2));
  options.depth_noise_at_1m = synth.depth_noise_at_1m;
  MapAndReport(state, scene.camera(), options, static_cast<std::size_t>(scene.num_frames()), [&](std::size_t i) {
    const SynthFrame frame = scene.RenderFrame(static_cast<int>(i));
    return DenseKeyframe{static_cast<long>(i), frame.timestamp, frame.world_from_cam, frame.bgr, frame.depth_m, cv::Mat()};
  });
}
BENCHMARK(BM_DenseMap_SynthStatic)
    ->Args({10, 0, 1})->Args({1, 0, 1})->Args({10, 15, 0})->Args({10, 15, 1})->Args({1, 15, 1})
    ->Iterations(1)->Unit(benchmark::kMillisecond);

void BM_DenseMap_Bonn(benchmark::State& state) { MapSequence(state, "bonn_crowd_dev", "bonn.yaml"); }
BENCHMARK(BM_DenseMap_Bonn)->Args({10, 0})->Args({10, 1})->Args({1, 1})->Iterations(1)->Unit(benchmark::kMillisecond);

void BM_DenseMap_TumRpy(benchmark::State& state) { MapSequence(state, "tum_fr1_rpy_dev", "tum_fr1.yaml"); }
BENCHMARK(BM_DenseMap_TumRpy)->Args({10, 0})->Args({10, 1})->Args({1, 1})->Iterations(1)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace esdslam

BENCHMARK_MAIN();
