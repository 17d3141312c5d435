#include "eval/ate.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "common/error.h"
#include "eval/alignment.h"
#include "eval/error_stats.h"

namespace esdslam {
namespace {

StampedPose Pose(double t, const Vec3& position, const Quat& rotation = Quat::Identity()) {
  return {t, Rigid3(rotation, position)};
}

const Rigid3 kTransform(Quat(Eigen::AngleAxisd(0.7, Vec3(0.3, -0.5, 0.8).normalized())), Vec3(2.0, -1.0, 0.5));

TEST(ErrorStats, MatchesHandComputedValues) {
  const ErrorStats odd = ComputeErrorStats({3, 1, 2});
  EXPECT_DOUBLE_EQ(odd.median, 2);
  EXPECT_DOUBLE_EQ(odd.mean, 2);
  EXPECT_DOUBLE_EQ(odd.rmse, std::sqrt(14.0 / 3.0));
  EXPECT_DOUBLE_EQ(odd.std, std::sqrt(2.0 / 3.0));  // population std
  EXPECT_DOUBLE_EQ(odd.min, 1);
  EXPECT_DOUBLE_EQ(odd.max, 3);
  EXPECT_EQ(odd.count, 3u);
  EXPECT_DOUBLE_EQ(ComputeErrorStats({4, 1, 3, 2}).median, 2.5);
  EXPECT_THROW(ComputeErrorStats({}), Error);
}

TEST(Alignment, RecoversRigidAndSimilarityTransforms) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uniform(-2, 2);
  std::vector<Vec3> source, target_rigid, target_scaled;
  for (int i = 0; i < 20; ++i) {
    source.emplace_back(uniform(rng), uniform(rng), uniform(rng));
    target_rigid.push_back(kTransform * source.back());
    target_scaled.push_back(kTransform.rotation() * (2.5 * source.back()) + kTransform.translation());
  }
  const Similarity3 rigid = AlignPoints(source, target_rigid, false);
  EXPECT_NEAR((rigid.rotation - kTransform.rotation_matrix()).norm(), 0, 1e-9);
  EXPECT_NEAR((rigid.translation - kTransform.translation()).norm(), 0, 1e-9);
  EXPECT_DOUBLE_EQ(rigid.scale, 1.0);
  const Similarity3 similarity = AlignPoints(source, target_scaled, true);
  EXPECT_NEAR(similarity.scale, 2.5, 1e-9);
  EXPECT_NEAR((similarity.rotation - kTransform.rotation_matrix()).norm(), 0, 1e-9);
  EXPECT_THROW(AlignPoints({Vec3::Zero(), Vec3::Ones()}, {Vec3::Zero(), Vec3::Ones()}, false), Error);
}

TEST(Alignment, NeverReturnsAReflection) {
  // Planar mirrored points: the best proper rotation, not the mirror.
  const std::vector<Vec3> source = {{1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -2, 0}};
  std::vector<Vec3> target;
  for (const Vec3& p : source) target.emplace_back(p.x(), -p.y(), p.z());
  const Similarity3 result = AlignPoints(source, target, false);
  EXPECT_NEAR(result.rotation.determinant(), 1.0, 1e-12);
}

TEST(Ate, RigidlyMovedGroundTruthHasZeroError) {
  std::vector<StampedPose> groundtruth, estimate;
  for (int i = 0; i < 50; ++i) {
    const double t = 100.0 + 0.01 * i;
    const Vec3 position(std::sin(0.2 * i), std::cos(0.13 * i), 0.02 * i);
    groundtruth.push_back(Pose(t, position));
    if (i % 3 == 0) estimate.push_back(Pose(t + 0.004, kTransform * position));  // within 0.02 s
  }
  const AteResult result = ComputeAte(groundtruth, estimate);
  EXPECT_EQ(result.translation_m.count, estimate.size());
  EXPECT_NEAR(result.translation_m.rmse, 0, 1e-9);
  EXPECT_NEAR(result.translation_m.max, 0, 1e-9);
  EXPECT_NEAR((result.groundtruth_from_estimate.rotation - kTransform.inverse().rotation_matrix()).norm(), 0, 1e-9);
}

// Cube corners, estimate displaced along z by d = 0.1 xyz + 0.05 xy, which is orthogonal to 1, x,
// y and z over the corners: the best alignment stays the identity and per-pair errors are |d|:
// four of 0.15 and four of 0.05 -> rmse sqrt(0.0125), mean 0.1, median 0.1, std 0.05.
TEST(Ate, KnownPerPairErrorsGiveKnownStatistics) {
  std::vector<StampedPose> groundtruth, estimate;
  int i = 0;
  for (int x : {-1, 1}) {
    for (int y : {-1, 1}) {
      for (int z : {-1, 1}) {
        const Vec3 position(x, y, z);
        const double displacement = 0.1 * x * y * z + 0.05 * x * y;
        groundtruth.push_back(Pose(i, position));
        estimate.push_back(Pose(i, kTransform * (position + Vec3(0, 0, displacement))));
        ++i;
      }
    }
  }
  const AteResult result = ComputeAte(groundtruth, estimate);
  EXPECT_NEAR(result.translation_m.rmse, std::sqrt(0.0125), 1e-12);
  EXPECT_NEAR(result.translation_m.mean, 0.1, 1e-12);
  EXPECT_NEAR(result.translation_m.median, 0.1, 1e-12);
  EXPECT_NEAR(result.translation_m.std, 0.05, 1e-12);
  EXPECT_NEAR(result.translation_m.min, 0.05, 1e-12);
  EXPECT_NEAR(result.translation_m.max, 0.15, 1e-12);
  EXPECT_EQ(result.translation_m.count, 8u);
}

TEST(Ate, AssociationRespectsMaxDifferenceAndOffset) {
  std::vector<StampedPose> groundtruth, estimate;
  for (int i = 0; i < 10; ++i) {
    groundtruth.push_back(Pose(i, Vec3(i, i * i * 0.1, 0)));
    estimate.push_back(Pose(i + 0.5, Vec3(i, i * i * 0.1, 0)));  // 0.5 s late
  }
  EXPECT_THROW(ComputeAte(groundtruth, estimate), Error);  // nothing within 0.02 s
  AteOptions options;
  options.time_offset = -0.5;
  const AteResult result = ComputeAte(groundtruth, estimate, options);
  EXPECT_EQ(result.translation_m.count, 10u);
  EXPECT_NEAR(result.translation_m.rmse, 0, 1e-9);
  options.time_offset = 0;
  options.max_time_difference = 0.5;
  EXPECT_EQ(ComputeAte(groundtruth, estimate, options).translation_m.count, 10u);  // boundary inclusive
}

TEST(Ate, ScaleOptionRemovesScaleError) {
  std::vector<StampedPose> groundtruth, estimate;
  for (int i = 0; i < 30; ++i) {
    const Vec3 position(std::sin(0.3 * i), 0.1 * i, std::cos(0.2 * i));
    groundtruth.push_back(Pose(i, position));
    estimate.push_back(Pose(i, kTransform * (0.5 * position)));
  }
  EXPECT_GT(ComputeAte(groundtruth, estimate).translation_m.rmse, 0.1);
  AteOptions options;
  options.with_scale = true;
  const AteResult scaled = ComputeAte(groundtruth, estimate, options);
  EXPECT_NEAR(scaled.translation_m.rmse, 0, 1e-9);
  EXPECT_NEAR(scaled.groundtruth_from_estimate.scale, 2.0, 1e-9);
}

}  // namespace
}  // namespace esdslam
