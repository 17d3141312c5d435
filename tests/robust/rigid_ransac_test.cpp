#include "robust/rigid_ransac.h"

#include <random>

#include <gtest/gtest.h>

#include "common/error.h"

namespace esdslam {
namespace {

constexpr double kDegree = M_PI / 180.0;

PinholeCamera TestCamera() {
  CameraIntrinsics intrinsics;
  intrinsics.fx = intrinsics.fy = 525.0;
  intrinsics.cx = 319.5;
  intrinsics.cy = 239.5;
  return PinholeCamera(intrinsics);
}

// 100 matches of points seen by both cameras; the first 40 % are outliers (point_b moved).
std::vector<PointMatch3D> MakeMatches(const Sim3Transform& a_from_b, const PinholeCamera& camera, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0), depth(1.0, 4.0);
  const Sim3Transform b_from_a = a_from_b.inverse();
  std::vector<PointMatch3D> matches;
  while (matches.size() < 100) {
    PointMatch3D m;
    m.point_a = Vec3(u(rng), 0.7 * u(rng), depth(rng));
    m.point_b = b_from_a * m.point_a;
    if (m.point_b.z() < 0.5) continue;
    m.pixel_a = camera.Project(m.point_a);
    m.pixel_b = camera.Project(m.point_b);
    if (matches.size() < 40) {
      m.point_b += Vec3(u(rng), u(rng), u(rng)) * 0.5 + Vec3(0.2, 0.2, 0.2);
      m.pixel_b = camera.Project(m.point_b);
    }
    matches.push_back(m);
  }
  return matches;
}

Sim3Transform KnownTransform(double scale) {
  Sim3Transform t;
  t.rigid = Rigid3(ExpSO3(Vec3(0.1, -0.25, 0.15)), Vec3(0.3, -0.1, 0.2));
  t.scale = scale;
  return t;
}

void ExpectRecovered(const RigidRansacResult& result, const Sim3Transform& truth) {
  ASSERT_TRUE(result.success);
  EXPECT_LT((result.a_from_b.rigid.translation() - truth.rigid.translation()).norm(), 1e-3);
  EXPECT_LT(RotationAngle(result.a_from_b.rigid.rotation().conjugate() * truth.rigid.rotation()), 0.01 * kDegree);
  EXPECT_NEAR(result.a_from_b.scale, truth.scale, 1e-6);
  EXPECT_EQ(result.num_inliers, 60);
  for (int i = 0; i < 100; ++i) EXPECT_EQ(result.inliers[i], i >= 40) << i;
}

TEST(RigidRansacTest, RecoversTransformWithFortyPercentOutliersReprojection) {
  const PinholeCamera camera = TestCamera();
  const Sim3Transform truth = KnownTransform(1.0);
  const RigidRansacResult result = EstimateRigidRansac(MakeMatches(truth, camera, 1), RigidRansacOptions(), &camera, &camera);
  ExpectRecovered(result, truth);
  EXPECT_LT(result.iterations, 100);  // adaptive stop at 60 % inliers: ~19 samples
}

TEST(RigidRansacTest, RecoversTransformMetricMode) {
  const PinholeCamera camera = TestCamera();
  const Sim3Transform truth = KnownTransform(1.0);
  RigidRansacOptions options;
  options.mode = RigidRansacOptions::ErrorMode::kMetric;
  options.max_error_m = 0.02;
  ExpectRecovered(EstimateRigidRansac(MakeMatches(truth, camera, 2), options), truth);
}

TEST(RigidRansacTest, RecoversScaleWhenAsked) {
  const PinholeCamera camera = TestCamera();
  const Sim3Transform truth = KnownTransform(1.25);
  RigidRansacOptions options;
  options.estimate_scale = true;
  ExpectRecovered(EstimateRigidRansac(MakeMatches(truth, camera, 3), options, &camera, &camera), truth);
}

TEST(RigidRansacTest, SameSeedSameResultAndFailsOnPureOutliers) {
  const PinholeCamera camera = TestCamera();
  std::vector<PointMatch3D> matches = MakeMatches(KnownTransform(1.0), camera, 4);
  const RigidRansacResult a = EstimateRigidRansac(matches, RigidRansacOptions(), &camera, &camera);
  const RigidRansacResult b = EstimateRigidRansac(matches, RigidRansacOptions(), &camera, &camera);
  EXPECT_EQ(a.iterations, b.iterations);
  EXPECT_EQ(a.inliers, b.inliers);
  matches.resize(40);  // outliers only
  EXPECT_FALSE(EstimateRigidRansac(matches, RigidRansacOptions(), &camera, &camera).success);
  EXPECT_THROW(EstimateRigidRansac(matches, RigidRansacOptions()), Error);  // reprojection needs cameras
}

TEST(AlignPointSetsTest, ExactOnThreePointsAndRejectsCollinear) {
  const Sim3Transform truth = KnownTransform(1.0);
  const std::vector<Vec3> b{Vec3(0, 0, 1), Vec3(1, 0, 2), Vec3(0, 1, 3)};
  std::vector<Vec3> a;
  for (const Vec3& p : b) a.push_back(truth * p);
  Sim3Transform estimate;
  ASSERT_TRUE(AlignPointSets(a, b, false, &estimate));
  EXPECT_LT((estimate.rigid.translation() - truth.rigid.translation()).norm(), 1e-9);
  const std::vector<Vec3> collinear{Vec3(0, 0, 1), Vec3(1, 1, 1), Vec3(2, 2, 1)};
  EXPECT_FALSE(AlignPointSets(collinear, collinear, false, &estimate));
}

}  // namespace
}  // namespace esdslam
