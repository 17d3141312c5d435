// Golden run on the synthetic "occlusion" preset (issue 13): a pair of people crosses 0.9 m in
// front of the camera and covers 75-85 % of the image for about 1.5 s (frames ~104-152), and the
// sensor is blocked for 4 frames (210-213: 2 % valid depth, a dark image). Perfect VOC labels
// through the folder segmenter, every frame's own labels, single thread (the run repeats exactly),
// so what is measured is tracking with a small static area, not the segmentation.
//
// Expected: every frame has a pose (the blocked frames coast on the motion model instead of being
// lost, and tracking resumes without a relocalization), and the error while the pair covers the
// view stays within a few centimetres. Issue 13's target (the largest error during the occlusion at
// most 3x the sequence's median error) is printed, not asserted: it is not met yet (docs/RESULTS.md).
#include <algorithm>
#include <filesystem>

#include <gtest/gtest.h>

#include "eval/ate.h"
#include "io/frame_source.h"
#include "io/trajectory_io.h"
#include "io/tum_sequence.h"
#include "synth/synthetic_scene.h"
#include "system/dynamic_sequence.h"
#include "system/pipeline.h"
#include "system/run_loop.h"
#include "support/temp_path.h"

namespace esdslam {
namespace {

constexpr int kOcclusionFirst = 100, kOcclusionLast = 160;  // the pair covers > 50 % of the image
constexpr int kBlockedFirst = 210, kBlockedFrames = 4;

TEST(OcclusionSlowTest, EveryFrameHasAPoseAndTheErrorStaysSmallWhilePeopleCoverTheView) {
  const std::string dir = testing::OcclusionTestSequence();
  ASSERT_EQ(SynthPreset("occlusion").blocked_frame, kBlockedFirst);
  RunFlags flags;
  flags.segment_every = 1;
  flags.single_thread = true;
  flags.mode = DynamicMode::kFull;
  const RunConfig config = ResolveRunConfig(LoadRunSettings(dir + "/run.yaml"), flags);
  TumFolderSource source(TumSequence::Open(dir).frames(), config.settings.core.depth_map_factor);
  Pipeline run(config);
  int with_pose = 0, coasted = 0, coasted_blocked = 0;
  RunFrames(source, run, [&](const FrameReport& report) {
    with_pose += report.track.has_pose;
    coasted += report.track.coasted;
    coasted_blocked += report.track.coasted && report.index >= kBlockedFirst && report.index < kBlockedFirst + kBlockedFrames;
  });
  run.Finish(testing::TestTempPath("occlusion_run_out"));
  const int frames = SynthPreset("occlusion").num_frames;
  EXPECT_EQ(with_pose, frames);
  EXPECT_EQ(coasted_blocked, kBlockedFrames);
  EXPECT_EQ(coasted, kBlockedFrames) << "only the blocked frames are blind";
  EXPECT_EQ(run.system().relocalizations(), 0) << "tracking resumes after the blocked frames without relocalizing";

  const std::vector<StampedPose> truth = ReadTumTrajectory(dir + "/groundtruth.txt");
  const AteResult ate = ComputeAte(truth, run.system().Trajectory());
  std::vector<double> all, during;
  for (const AtePair& pair : ate.pairs) {
    all.push_back(pair.error_m);
    const auto frame = static_cast<int>(pair.groundtruth_index);  // one ground-truth pose per frame
    if (frame >= kOcclusionFirst && frame <= kOcclusionLast) during.push_back(pair.error_m);
  }
  ASSERT_FALSE(during.empty());
  std::sort(all.begin(), all.end());
  const double median = all[all.size() / 2];
  const double worst_during = *std::max_element(during.begin(), during.end());
  std::printf("occlusion preset: ATE RMSE %.4f m, median %.4f m; during the occlusion max %.4f m = %.1fx the median "
              "(issue 13 target: <= 3x)\n",
              ate.translation_m.rmse, median, worst_during, worst_during / median);
  EXPECT_LT(ate.translation_m.rmse, 0.012);  // this build: 0.0071 m
  EXPECT_LT(worst_during, 0.04);  // this build: 0.025 m (0.020 m with Tracking.motionPriorBelowMatches: 150)
}

}  // namespace
}  // namespace esdslam
