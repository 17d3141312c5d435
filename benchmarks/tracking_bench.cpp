// Per-frame cost of ORB extraction (Frame construction) and of the tracking step on the dev
// sequences (TUM fr1_rpy, Bonn crowd). The tracking benchmark runs the full system (local mapping
// and loop closing on their own threads, no segmentation) over the sequence; its manual time is
// the whole tracking step of a frame (Frame construction with ORB extraction + tracking), and the
// counters extract_ms / track_ms split it (means per frame).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "io/settings.h"
#include "io/tum_sequence.h"
#include "system/slam_system.h"
#include "tracking/frame.h"

namespace esdslam {
namespace {

struct Dataset {
  Settings settings;
  std::vector<double> timestamps;
  std::vector<RgbdImages> images;
};

const Dataset* LoadDataset(const std::string& name, const std::string& settings_file) {
  static std::map<std::string, std::unique_ptr<Dataset>> cache;
  auto& slot = cache[name];
  if (slot) return slot.get();
  const std::string dir = std::string(ESDSLAM_TEST_DATA_DIR) + "/data/" + name;
  if (!std::filesystem::exists(dir)) return nullptr;
  auto data = std::make_unique<Dataset>();
  data->settings = LoadSettings(std::string(ESDSLAM_SOURCE_DIR) + "/config/" + settings_file);
  const TumSequence sequence = TumSequence::Open(dir);
  for (const FrameEntry& entry : sequence.frames()) {
    data->timestamps.push_back(entry.timestamp);
    data->images.push_back(LoadRgbd(entry, data->settings.depth_map_factor));
  }
  slot = std::move(data);
  return slot.get();
}

void BM_OrbExtraction(benchmark::State& state, const std::string& name, const std::string& settings_file) {
  const Dataset* data = LoadDataset(name, settings_file);
  if (data == nullptr) {
    state.SkipWithError("dataset not found");
    return;
  }
  const OrbExtractor extractor(data->settings.orb);
  const auto rig = MakeRgbdRig(data->settings.camera, data->settings.bf, data->settings.th_depth, extractor);
  std::size_t i = 0;
  for (auto _ : state) {
    const RgbdImages& image = data->images[i++ % data->images.size()];
    Frame frame(0, 0.0, image.bgr, image.depth_m, cv::Mat(), extractor, rig);
    benchmark::DoNotOptimize(frame.size());
  }
}

void BM_TrackingStep(benchmark::State& state, const std::string& name, const std::string& settings_file) {
  const Dataset* data = LoadDataset(name, settings_file);
  if (data == nullptr) {
    state.SkipWithError("dataset not found");
    return;
  }
  std::unique_ptr<SlamSystem> system;
  std::size_t i = 0;
  int lost = 0;
  double extract_ms = 0, track_ms = 0;
  for (auto _ : state) {
    if (i % data->images.size() == 0) system = std::make_unique<SlamSystem>(data->settings, SlamOptions{});
    const std::size_t k = i++ % data->images.size();
    const TrackOutcome outcome = system->TrackRgbd(data->images[k].bgr, data->images[k].depth_m, data->timestamps[k]);
    lost += !outcome.has_pose;
    extract_ms += outcome.extract_ms, track_ms += outcome.track_ms;
    state.SetIterationTime((outcome.extract_ms + outcome.track_ms) / 1000.0);
  }
  const double frames = static_cast<double>(std::max<std::size_t>(1, i));
  state.counters["lost"] = lost;
  state.counters["extract_ms"] = extract_ms / frames;
  state.counters["track_ms"] = track_ms / frames;
}

BENCHMARK_CAPTURE(BM_OrbExtraction, tum_fr1_rpy, std::string("tum_fr1_rpy_dev"), std::string("tum_fr1.yaml"))
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_OrbExtraction, bonn_crowd, std::string("bonn_crowd_dev"), std::string("bonn.yaml"))
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_TrackingStep, tum_fr1_rpy, std::string("tum_fr1_rpy_dev"), std::string("tum_fr1.yaml"))
    ->UseManualTime()
    ->Iterations(120)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_TrackingStep, bonn_crowd, std::string("bonn_crowd_dev"), std::string("bonn.yaml"))
    ->UseManualTime()
    ->Iterations(250)
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace esdslam

BENCHMARK_MAIN();
