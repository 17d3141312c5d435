// Map save/load and localization-only mode on TUM fr1_rpy (dev window): the map saved by a SLAM
// run is reloaded, the same sequence is localized in it frame by frame (starting LOST, i.e. by
// BoW relocalization), every frame gets a pose, no keyframe is added and the ATE stays close to
// the SLAM run's.
#include <gtest/gtest.h>

#include <filesystem>

#include "eval/ate.h"
#include "io/settings.h"
#include "io/tum_sequence.h"
#include "system/slam_system.h"
#include "support/temp_path.h"
#include "support/test_paths.h"

namespace esdslam {
namespace {

const std::string kDir = ::esdslam::testing::TestDataDir() + "/data/tum_fr1_rpy_dev";

struct PassResult {
  int tracked = 0, frames = 0, keyframes = 0, relocalizations = 0;
  double ate_rmse = 0;
};

PassResult RunPass(const SlamOptions& options, const std::string& save_map) {
  const Settings settings = LoadSettings(::esdslam::testing::SourceDir() + "/config/tum_fr1.yaml");
  const TumSequence sequence = TumSequence::Open(kDir);
  SlamSystem system(settings, options);
  PassResult result;
  const int keyframes_at_start = system.num_keyframes();
  for (const FrameEntry& entry : sequence.frames()) {
    const RgbdImages images = LoadRgbd(entry, settings.depth_map_factor);
    result.tracked += system.TrackRgbd(images.bgr, images.depth_m, entry.timestamp).has_pose;
    ++result.frames;
  }
  system.Shutdown();
  if (!save_map.empty()) system.SaveMap(save_map);
  result.keyframes = system.num_keyframes() - keyframes_at_start;
  result.relocalizations = system.relocalizations();
  result.ate_rmse = ComputeAte(ReadTumTrajectory(sequence.groundtruth_path()), system.Trajectory()).translation_m.rmse;
  return result;
}

TEST(LocalizationSlowTest, SavedMapReloadsAndLocalizesEveryFrame) {
  if (!std::filesystem::exists(kDir)) GTEST_SKIP() << kDir << " not found";
  const std::string map_path = testing::TestTempPath("localization_test", ".map");
  SlamOptions slam;
  slam.single_thread = true;
  const PassResult mapping = RunPass(slam, map_path);
  ASSERT_EQ(mapping.tracked, mapping.frames);

  SlamOptions localization = slam;
  localization.load_map = map_path;
  localization.tracker.localization_only = true;
  const PassResult located = RunPass(localization, "");
  std::printf("SLAM: %d keyframes, ATE %.4f m; localization: %d/%d frames tracked, %d keyframes added, "
              "%d relocalizations, ATE %.4f m\n",
              mapping.keyframes, mapping.ate_rmse, located.tracked, located.frames, located.keyframes,
              located.relocalizations, located.ate_rmse);
  EXPECT_EQ(located.tracked, located.frames);
  EXPECT_EQ(located.keyframes, 0);
  EXPECT_GE(located.relocalizations, 1);
  EXPECT_LE(located.ate_rmse, 1.25 * mapping.ate_rmse);
  std::filesystem::remove(map_path);
}

}  // namespace
}  // namespace esdslam
