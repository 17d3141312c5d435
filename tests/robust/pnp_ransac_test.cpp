#include "robust/pnp_ransac.h"

#include <random>

#include <gtest/gtest.h>

namespace esdslam {
namespace {

TEST(PnpRansacTest, RecoversKnownPoseWithOutliers) {
  CameraIntrinsics intrinsics;
  intrinsics.fx = 517.3;
  intrinsics.fy = 516.5;
  intrinsics.cx = 318.6;
  intrinsics.cy = 255.3;
  const PinholeCamera camera(intrinsics);
  const Rigid3 cam_from_world(ExpSO3(Vec3(0.2, -0.4, 0.1)), Vec3(-0.5, 0.2, 1.0));
  const Rigid3 world_from_cam = cam_from_world.inverse();
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> u(-1.0, 1.0), depth(0.8, 5.0), pixel_noise(-0.3, 0.3);
  std::vector<Vec3> points;
  std::vector<Vec2> pixels;
  for (int i = 0; i < 150; ++i) {
    const Vec3 p_cam(u(rng) * 1.5, u(rng), depth(rng));
    points.push_back(world_from_cam * p_cam);
    Vec2 pixel = camera.Project(p_cam) + Vec2(pixel_noise(rng), pixel_noise(rng));
    if (i % 3 == 0) pixel += Vec2(40.0 + 100.0 * std::abs(u(rng)), -30.0);  // one third outliers
    pixels.push_back(pixel);
  }
  const PnpRansacResult result = EstimatePnpRansac(points, pixels, camera, PnpRansacOptions());
  ASSERT_TRUE(result.success);
  EXPECT_EQ(result.num_inliers, 100);
  for (int i = 0; i < 150; ++i) EXPECT_EQ(result.inliers[i], i % 3 != 0) << i;
  EXPECT_LT((result.cam_from_world.translation() - cam_from_world.translation()).norm(), 0.01);
  EXPECT_LT(RotationAngle(result.cam_from_world.rotation().conjugate() * cam_from_world.rotation()), 0.2 * M_PI / 180);
  // Deterministic.
  const PnpRansacResult again = EstimatePnpRansac(points, pixels, camera, PnpRansacOptions());
  EXPECT_EQ(again.iterations, result.iterations);
  EXPECT_EQ(again.cam_from_world.translation(), result.cam_from_world.translation());
}

TEST(PnpRansacTest, FailsWithoutConsistentMatches) {
  CameraIntrinsics intrinsics;
  intrinsics.fx = intrinsics.fy = 500;
  intrinsics.cx = 320;
  intrinsics.cy = 240;
  const PinholeCamera camera(intrinsics);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Vec3> points;
  std::vector<Vec2> pixels;
  for (int i = 0; i < 60; ++i) {
    points.emplace_back(u(rng) - 0.5, u(rng) - 0.5, 1.0 + 3.0 * u(rng));
    pixels.emplace_back(640 * u(rng), 480 * u(rng));
  }
  EXPECT_FALSE(EstimatePnpRansac(points, pixels, camera, PnpRansacOptions()).success);
}

}  // namespace
}  // namespace esdslam
