// Golden runs of the dynamic stages on the real dev windows (ONNX ESPNetv2 segmenter, every-frame
// hand-off, single-thread: the runs repeat exactly, so one run per mode is enough).
//   Bonn crowd: full mode (and semantic mode) track every frame, ATE RMSE <= 0.018 m and <= 1/5
//               of mode none (ORB-SLAM2 dropping keypoints on dilated ESPNetv2 person masks:
//               0.0154 m, losing track for 7-11 frames in 2 of 3 runs).
//   TUM fr1_rpy (static scene): full mode not worse than none by more than 10 %, and the geometry
//               check finds (almost) nothing moving there.
#include <gtest/gtest.h>

#include <filesystem>

#include "eval/ate.h"
#include "io/trajectory_io.h"
#include "io/tum_sequence.h"
#include "system/pipeline.h"
#include "system/run_loop.h"
#include "support/temp_path.h"
#include "support/test_paths.h"

namespace esdslam {
namespace {

const std::string kData = ::esdslam::testing::TestDataDir() + "/data/";

struct ModeResult {
  int tracked = 0, frames = 0;
  double ate_rmse = 0;
  long geometry_keypoints = 0, keypoints = 0;
};

ModeResult RunMode(const std::string& dir, const std::string& settings_file, DynamicMode mode) {
  RunFlags flags;
  flags.single_thread = true;
  flags.mode = mode;
  const RunConfig config =
      ResolveRunConfig(LoadRunSettings(::esdslam::testing::SourceDir() + "/config/" + settings_file), flags);
  const TumSequence sequence = TumSequence::Open(dir);
  TumFolderSource source(sequence.frames(), config.settings.core.depth_map_factor);
  Pipeline run(config);
  ModeResult result;
  RunFrames(source, run, [&result](const FrameReport& report) {
    result.tracked += report.track.has_pose;
    result.geometry_keypoints += report.keypoints.by_geometry;
    result.keypoints += report.keypoints.total;
    ++result.frames;
  });
  run.Finish(testing::TestTempPath("dynamic_golden"));
  result.ate_rmse =
      ComputeAte(ReadTumTrajectory(sequence.groundtruth_path()), run.system().Trajectory()).translation_m.rmse;
  std::printf("%s mode %s: tracked %d/%d, ATE RMSE %.4f m, %ld of %ld keypoints dropped by geometry\n", dir.c_str(),
              ToString(mode), result.tracked, result.frames, result.ate_rmse, result.geometry_keypoints,
              result.keypoints);
  return result;
}

TEST(DynamicGoldenSlowTest, BonnCrowdFullAndSemanticModesBeatPlainSlamFiveTimes) {
  const std::string dir = kData + "bonn_crowd_dev";
  if (!std::filesystem::exists(dir)) GTEST_SKIP() << dir << " not found";
  const ModeResult none = RunMode(dir, "bonn.yaml", DynamicMode::kNone);
  for (const DynamicMode mode : {DynamicMode::kFull, DynamicMode::kSemantic}) {
    const ModeResult result = RunMode(dir, "bonn.yaml", mode);
    EXPECT_EQ(result.tracked, result.frames) << ToString(mode);
    EXPECT_LE(result.ate_rmse, 0.018) << ToString(mode);
    EXPECT_LE(result.ate_rmse, none.ate_rmse / 5) << ToString(mode);
  }
}

TEST(DynamicGoldenSlowTest, TumFr1RpyFullModeCostsAtMostTenPercent) {
  const std::string dir = kData + "tum_fr1_rpy_dev";
  if (!std::filesystem::exists(dir)) GTEST_SKIP() << dir << " not found";
  const ModeResult full = RunMode(dir, "tum_fr1.yaml", DynamicMode::kFull);
  const ModeResult none = RunMode(dir, "tum_fr1.yaml", DynamicMode::kNone);
  EXPECT_EQ(full.tracked, full.frames);
  EXPECT_LE(full.ate_rmse, 1.1 * none.ate_rmse);
  EXPECT_LE(none.ate_rmse, 0.020);  // issue 13's limit; 0.0118 m measured (single thread)
  EXPECT_LE(full.geometry_keypoints, full.keypoints / 100);  // a static scene: nothing moves
}

}  // namespace
}  // namespace esdslam
