#include "eval/rpe.h"

#include <cmath>

#include <gtest/gtest.h>

#include "common/error.h"

namespace esdslam {
namespace {

constexpr double kPi = 3.14159265358979323846;

Quat Yaw(double degrees) { return Quat(Eigen::AngleAxisd(degrees * kPi / 180.0, Vec3::UnitZ())); }

// Ground truth: 1 m along x per step, no rotation. Estimate: the same positions, but from pose 2
// on the camera is yawed by 10 degrees. Per-frame pairs (i, i+1):
//   (0,1): no error; (1,2): rotation error 10 deg, translation error 0;
//   (2,3), (3,4): rotation 0, translation |Rz(-10) x - x| = 2 sin(5 deg).
void MakeTrajectories(double dt, std::vector<StampedPose>& groundtruth, std::vector<StampedPose>& estimate) {
  for (int i = 0; i < 5; ++i) {
    groundtruth.push_back({i * dt, Rigid3(Quat::Identity(), Vec3(i, 0, 0))});
    estimate.push_back({i * dt, Rigid3(i >= 2 ? Yaw(10) : Quat::Identity(), Vec3(i, 0, 0))});
  }
}

TEST(Rpe, PerFrameMatchesHandComputedErrors) {
  std::vector<StampedPose> groundtruth, estimate;
  MakeTrajectories(1.0, groundtruth, estimate);
  const RpeResult result = ComputeRpe(groundtruth, estimate);
  const double e = 2 * std::sin(5 * kPi / 180.0);
  EXPECT_EQ(result.pairs, 4u);
  EXPECT_NEAR(result.translation_m.rmse, std::sqrt(2 * e * e / 4), 1e-12);
  EXPECT_NEAR(result.translation_m.mean, e / 2, 1e-12);
  EXPECT_NEAR(result.translation_m.median, e / 2, 1e-12);  // sorted {0, 0, e, e}
  EXPECT_NEAR(result.rotation_deg.rmse, 5.0, 1e-9);        // sqrt(100 / 4)
  EXPECT_NEAR(result.rotation_deg.mean, 2.5, 1e-9);
  EXPECT_NEAR(result.rotation_deg.median, 0.0, 1e-9);
  EXPECT_NEAR(result.rotation_deg.max, 10.0, 1e-9);
}

TEST(Rpe, InvariantToAGlobalTransformOfTheEstimate) {
  std::vector<StampedPose> groundtruth, estimate;
  MakeTrajectories(1.0, groundtruth, estimate);
  const Rigid3 transform(Quat(Eigen::AngleAxisd(1.0, Vec3(1, 1, 0).normalized())), Vec3(5, -3, 2));
  std::vector<StampedPose> moved = estimate;
  for (auto& pose : moved) pose.world_from_cam = transform * pose.world_from_cam;
  const RpeResult a = ComputeRpe(groundtruth, estimate), b = ComputeRpe(groundtruth, moved);
  EXPECT_NEAR(a.translation_m.rmse, b.translation_m.rmse, 1e-12);
  EXPECT_NEAR(a.rotation_deg.rmse, b.rotation_deg.rmse, 1e-9);
}

TEST(Rpe, DeltaInSeconds) {
  // Poses every 0.5 s: delta 1 s gives pairs (i, i+2): (0,2) and (1,3) span the yaw change: rot
  // 10 deg, trans 0; (2,4): rot 0, estimate motion Rz(-10) * 2x -> trans 2 * 2 sin(5 deg).
  std::vector<StampedPose> groundtruth, estimate;
  MakeTrajectories(0.5, groundtruth, estimate);
  RpeOptions options;
  options.unit = RpeOptions::DeltaUnit::kSeconds;
  options.delta = 1.0;
  const RpeResult result = ComputeRpe(groundtruth, estimate, options);
  const double e = 2 * std::sin(5 * kPi / 180.0);
  EXPECT_EQ(result.pairs, 3u);
  EXPECT_NEAR(result.translation_m.max, 2 * e, 1e-12);
  EXPECT_NEAR(result.translation_m.mean, 2 * e / 3, 1e-12);
  EXPECT_NEAR(result.rotation_deg.mean, 20.0 / 3.0, 1e-9);
}

TEST(Rpe, SkipsPairsWithoutGroundTruthAndFailsWithoutPairs) {
  std::vector<StampedPose> groundtruth, estimate;
  MakeTrajectories(1.0, groundtruth, estimate);
  groundtruth.erase(groundtruth.begin() + 1);  // gt at t=1 missing: pairs (0,1), (1,2) dropped
  RpeOptions options;
  options.max_time_difference = 0.1;
  const RpeResult result = ComputeRpe(groundtruth, estimate, options);
  EXPECT_EQ(result.pairs, 2u);
  options.unit = RpeOptions::DeltaUnit::kSeconds;
  options.delta = 10;  // longer than the trajectory
  EXPECT_THROW(ComputeRpe(groundtruth, estimate, options), Error);
  options.unit = RpeOptions::DeltaUnit::kFrames;
  options.delta = 1.5;
  EXPECT_THROW(ComputeRpe(groundtruth, estimate, options), Error);
}

}  // namespace
}  // namespace esdslam
