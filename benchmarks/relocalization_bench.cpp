// Relocalization cost on TUM fr1_rpy (dev window): a map from the first 60 frames (single-thread
// SLAM), then one BoW relocalization of frame 90 (BoW transform, database query, BoW matching,
// PnP RANSAC, pose optimisation, projection search) and the direct-index matching alone.
#include <filesystem>

#include <benchmark/benchmark.h>

#include "io/settings.h"
#include "io/tum_sequence.h"
#include "system/slam_system.h"
#include "tracking/relocalizer.h"

namespace esdslam {
namespace {

const std::string kDir = std::string(ESDSLAM_TEST_DATA_DIR) + "/data/tum_fr1_rpy_dev";

struct Fixture {
  Settings settings = LoadSettings(std::string(ESDSLAM_SOURCE_DIR) + "/config/tum_fr1.yaml");
  std::unique_ptr<SlamSystem> system;
  std::unique_ptr<OrbExtractor> extractor;
  Frame query;

  Fixture() {
    const TumSequence sequence = TumSequence::Open(kDir);
    SlamOptions options;
    options.single_thread = true;
    system = std::make_unique<SlamSystem>(settings, options);
    for (int i = 0; i < 60; ++i) {
      const RgbdImages images = LoadRgbd(sequence.frames()[i], settings.depth_map_factor);
      system->TrackRgbd(images.bgr, images.depth_m, sequence.frames()[i].timestamp);
    }
    system->Shutdown();
    extractor = std::make_unique<OrbExtractor>(settings.orb);
    const RgbdImages images = LoadRgbd(sequence.frames()[90], settings.depth_map_factor);
    query = Frame(1000, sequence.frames()[90].timestamp, images.bgr, images.depth_m, cv::Mat(), *extractor, system->rig());
  }
};

void BM_RelocalizeFrame(benchmark::State& state) {
  if (!std::filesystem::exists(kDir)) {
    state.SkipWithError("tum_fr1_rpy_dev not found");
    return;
  }
  Fixture fixture;
  Relocalizer relocalizer(fixture.system->place_recognition());
  const std::vector<KeyFrame*> keyframes = fixture.system->map().keyframes();
  int found = 0;
  for (auto _ : state) {
    Frame frame = fixture.query;
    found += relocalizer.Relocalize(&frame, PoseOptimizerOptions{}, keyframes) != nullptr;
  }
  state.counters["success_rate"] = static_cast<double>(found) / state.iterations();
  state.counters["keyframes"] = static_cast<double>(keyframes.size());
}
BENCHMARK(BM_RelocalizeFrame)->Unit(benchmark::kMillisecond);

void BM_DirectIndexMatch(benchmark::State& state) {
  if (!std::filesystem::exists(kDir)) {
    state.SkipWithError("tum_fr1_rpy_dev not found");
    return;
  }
  Fixture fixture;
  PlaceRecognition& places = *fixture.system->place_recognition();
  KeyFrame* keyframe = fixture.system->map().keyframes().back();
  const auto keyframe_bow = places.KeyFrameBow(keyframe);
  const ImageBow query_bow = places.Compute(fixture.query.features());
  int matches = 0;
  for (auto _ : state) {
    const std::vector<int> query_to_train = MatchByDirectIndex(keyframe->features(), keyframe_bow->direct_index, {},
                                                               fixture.query.features(), query_bow.direct_index, {},
                                                               BowMatchOptions{});
    matches = static_cast<int>(std::count_if(query_to_train.begin(), query_to_train.end(), [](int t) { return t >= 0; }));
  }
  state.counters["matches"] = matches;
}
BENCHMARK(BM_DirectIndexMatch)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace esdslam

BENCHMARK_MAIN();
