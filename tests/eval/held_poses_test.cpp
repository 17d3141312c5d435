// Holding the newest pose at frames without one: own poses kept, gaps (dropped, lost frames)
// filled with the pose before them, frames before the first pose left out and counted.
#include <gtest/gtest.h>

#include "eval/ate.h"
#include "eval/held_poses.h"

namespace esdslam {
namespace {

StampedPose At(double t, double x) {
  StampedPose pose;
  pose.timestamp = t;
  pose.world_from_cam = Rigid3(Mat3::Identity(), Vec3(x, 0, 0));
  return pose;
}

TEST(HeldPosesTest, FramesWithoutAPoseHoldTheNewestEarlierOne) {
  // Frames at 0.0 .. 0.5; the estimate has 0.1 (stamp rounded to 6 decimals), 0.2 and 0.5.
  const std::vector<StampedPose> estimate = {At(0.1000004, 1), At(0.2, 2), At(0.5, 5)};
  const HeldTrajectory held = HoldPosesAtFrames(estimate, {0.0, 0.1, 0.2, 0.3, 0.4, 0.5});
  EXPECT_EQ(held.frames, 6u);
  EXPECT_EQ(held.before_first, 1u);  // 0.0: nothing to hold yet
  EXPECT_EQ(held.with_pose, 3u);
  EXPECT_EQ(held.held, 2u);  // 0.3 and 0.4 hold the pose of 0.2
  ASSERT_EQ(held.poses.size(), 5u);
  const double expected_x[] = {1, 2, 2, 2, 5};
  const double expected_t[] = {0.1, 0.2, 0.3, 0.4, 0.5};
  for (std::size_t i = 0; i < held.poses.size(); ++i) {
    EXPECT_EQ(held.poses[i].timestamp, expected_t[i]) << i;  // at the frame's own time
    EXPECT_EQ(held.poses[i].world_from_cam.translation().x(), expected_x[i]) << i;
  }
}

TEST(HeldPosesTest, AnEstimateAtEveryFrameIsUnchangedAndNoFramesGiveNothing) {
  const std::vector<StampedPose> estimate = {At(1, 1), At(2, 2)};
  const HeldTrajectory held = HoldPosesAtFrames(estimate, {1, 2});
  EXPECT_EQ(held.with_pose, 2u);
  EXPECT_EQ(held.held + held.before_first, 0u);
  EXPECT_EQ(held.poses[1].world_from_cam.translation().x(), 2);
  EXPECT_TRUE(HoldPosesAtFrames(estimate, {}).poses.empty());
  EXPECT_EQ(HoldPosesAtFrames({}, {1, 2}).before_first, 2u);
}

// The point of holding: a run that tracked only the first half looks perfect to the TUM ATE
// (missing poses left out) but not over all frames (the camera moved on without it).
TEST(HeldPosesTest, AteOverAllFramesChargesTheMissingFrames) {
  std::vector<StampedPose> truth, estimate;
  std::vector<double> frames;
  for (int i = 0; i < 10; ++i) {
    truth.push_back(At(i, 0.1 * i));
    frames.push_back(i);
    if (i < 5) estimate.push_back(At(i, 0.1 * i));
  }
  EXPECT_NEAR(ComputeAte(truth, estimate).translation_m.rmse, 0, 1e-9);
  const HeldTrajectory held = HoldPosesAtFrames(estimate, frames);
  EXPECT_EQ(held.held, 5u);
  EXPECT_GT(ComputeAte(truth, held.poses).translation_m.rmse, 0.05);
}

}  // namespace
}  // namespace esdslam
