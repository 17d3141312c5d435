// Golden runs of the whole system: TUM fr1_rpy (dev window), the synthetic static scene and the
// Bonn crowd window. ATE as the TUM benchmark defines it (rigid alignment).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include "eval/ate.h"
#include "io/settings.h"
#include "io/tum_sequence.h"
#include "synth/synthetic_scene.h"
#include "system/slam_system.h"
#include "support/test_paths.h"

namespace esdslam {
namespace {

const std::string kData = ::esdslam::testing::TestDataDir() + "/data/";

struct RunResult {
  int tracked = 0;
  int frames = 0;
  double ate_rmse = 0;
};

RunResult RunSequence(const std::string& dir, const std::string& settings_file, bool single_thread) {
  const Settings settings = LoadSettings(::esdslam::testing::SourceDir() + "/config/" + settings_file);
  const TumSequence sequence = TumSequence::Open(dir);
  SlamOptions options;
  options.single_thread = single_thread;
  SlamSystem system(settings, options);
  RunResult result;
  for (const FrameEntry& entry : sequence.frames()) {
    const RgbdImages images = LoadRgbd(entry, settings.depth_map_factor);
    result.tracked += system.TrackRgbd(images.bgr, images.depth_m, entry.timestamp).has_pose;
    ++result.frames;
  }
  system.Shutdown();
  result.ate_rmse = ComputeAte(ReadTumTrajectory(sequence.groundtruth_path()), system.Trajectory()).translation_m.rmse;
  return result;
}

double Median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

TEST(GoldenSlowTest, TumFr1RpyTracksEveryFrameWithinOrbSlam2Accuracy) {
  const std::string dir = kData + "tum_fr1_rpy_dev";
  if (!std::filesystem::exists(dir)) GTEST_SKIP() << dir << " not found";
  std::vector<double> ates;
  for (int run = 0; run < 3; ++run) {
    const RunResult result = RunSequence(dir, "tum_fr1.yaml", false);
    EXPECT_EQ(result.tracked, result.frames) << "run " << run;
    ates.push_back(result.ate_rmse);
    std::printf("fr1_rpy run %d: ATE RMSE %.4f m\n", run, result.ate_rmse);
  }
  // ORB-SLAM2 (built from source, median of 3): 0.0274 m; ours without the rolling-shutter
  // correction (Camera.readoutTime: 0) 0.021-0.039 m, with it 0.010-0.012 m (docs/RESULTS.md).
  EXPECT_LE(Median(ates), 0.016);
}

TEST(GoldenSlowTest, SyntheticStaticSceneIsTrackedToFiveMillimetres) {
  const SyntheticScene scene(SynthPreset("static"));
  Settings settings;
  settings.camera = scene.camera().intrinsics();
  SlamOptions options;
  options.single_thread = true;
  SlamSystem system(settings, options);
  int tracked = 0;
  for (int i = 0; i < scene.num_frames(); ++i) {
    const SynthFrame frame = scene.RenderFrame(i);
    tracked += system.TrackRgbd(frame.bgr, frame.depth_m, frame.timestamp).has_pose;
  }
  system.Shutdown();
  EXPECT_EQ(tracked, scene.num_frames());
  const double ate = ComputeAte(scene.GroundTruth(), system.Trajectory()).translation_m.rmse;
  std::printf("synthetic static: ATE RMSE %.4f m\n", ate);
  EXPECT_LE(ate, 0.005);
}

TEST(GoldenSlowTest, BonnCrowdRunsToTheEnd) {
  const std::string dir = kData + "bonn_crowd_dev";
  if (!std::filesystem::exists(dir)) GTEST_SKIP() << dir << " not found";
  const RunResult result = RunSequence(dir, "bonn.yaml", false);
  std::printf("bonn crowd: %d / %d tracked, ATE RMSE %.4f m\n", result.tracked, result.frames, result.ate_rmse);
  EXPECT_EQ(result.frames, 250);
  EXPECT_GT(result.tracked, result.frames / 2);  // no dynamic-object handling yet: accuracy not asserted
}

}  // namespace
}  // namespace esdslam
