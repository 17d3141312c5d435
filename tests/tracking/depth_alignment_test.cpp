#include "tracking/depth_alignment.h"

#include <cmath>

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include "common/error.h"
#include "optim/optim_test_scene.h"

namespace esdslam {
namespace {

PinholeCamera Camera() { return test::TumLikeCamera(); }

// A plane n . x = offset in the world frame.
struct Plane {
  Vec3 normal;
  double offset;
};

// The depth image (CV_32F m) a camera at world_from_cam sees of the nearest of `planes` along
// each pixel's ray; 0 where no plane is hit within 10 m.
cv::Mat Render(const PinholeCamera& camera, const Rigid3& world_from_cam, const std::vector<Plane>& planes) {
  cv::Mat depth(camera.height(), camera.width(), CV_32F, cv::Scalar(0.0f));
  const Vec3 origin = world_from_cam.translation();
  for (int v = 0; v < depth.rows; ++v)
    for (int u = 0; u < depth.cols; ++u) {
      const Vec3 ray_cam = camera.Backproject(Vec2(u, v), 1.0);  // z = 1
      const Vec3 ray = world_from_cam.rotation() * ray_cam;
      double best = 10.0;
      for (const Plane& plane : planes) {
        const double along = plane.normal.dot(ray);
        if (std::abs(along) < 1e-9) continue;
        const double s = (plane.offset - plane.normal.dot(origin)) / along;  // z of the hit
        if (s > 0.1 && s < best) best = s;
      }
      if (best < 10.0) depth.at<float>(v, u) = static_cast<float>(best);
    }
  return depth;
}

// Floor (y = 1.2, the camera's y points down), back wall (z = 3.5) and a side wall (x = -1.5):
// three planes, six constrained directions.
std::vector<Plane> Room() { return {{Vec3(0, 1, 0), 1.2}, {Vec3(0, 0, 1), 3.5}, {Vec3(1, 0, 0), -1.5}}; }

double CentreError(const Rigid3& a, const Rigid3& b) {
  return (a.inverse().translation() - b.inverse().translation()).norm();
}
double AngleDeg(const Rigid3& a, const Rigid3& b) { return RotationAngle(a.rotation() * b.rotation().conjugate()) * 180 / M_PI; }

TEST(AlignDepth, RecoversTheMotionBetweenTwoViewsOfARoom) {
  const PinholeCamera camera = Camera();
  const Rigid3 reference_cam_from_world = Rigid3::Identity();
  const Rigid3 truth = Rigid3(ExpSO3(Vec3(0.01, -0.02, 0.005)), Vec3(0.03, -0.01, 0.02)).inverse();  // cam_from_world
  const cv::Mat reference = Render(camera, reference_cam_from_world.inverse(), Room());
  const cv::Mat current = Render(camera, truth.inverse(), Room());
  const std::optional<DepthAlignment> aligned =
      AlignDepth(camera, current, cv::Mat(), reference, cv::Mat(), reference_cam_from_world, reference_cam_from_world);
  ASSERT_TRUE(aligned.has_value());
  EXPECT_LT(CentreError(aligned->cam_from_world, truth), 0.001);
  EXPECT_LT(AngleDeg(aligned->cam_from_world, truth), 0.02);
  EXPECT_GT(aligned->samples, 3000);
}

// One wall alone fixes the distance to it and the two tilts; sliding along it and turning about
// its normal are left free: three eigenvalues of the information matrix are zero (to rounding).
TEST(AlignDepth, AWallAloneLeavesItsInPlaneDirectionsFree) {
  const PinholeCamera camera = Camera();
  const std::vector<Plane> wall = {{Vec3(0, 0, 1), 2.0}};
  const cv::Mat depth = Render(camera, Rigid3::Identity(), wall);
  const std::optional<DepthAlignment> aligned =
      AlignDepth(camera, depth, cv::Mat(), depth, cv::Mat(), Rigid3::Identity(), Rigid3::Identity());
  ASSERT_TRUE(aligned.has_value());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eigen(aligned->information);
  const Vec6 values = eigen.eigenvalues();  // ascending
  EXPECT_LT(values(2), 1e-6 * values(5));
  EXPECT_GT(values(3), 1e-3 * values(5));
  EXPECT_LT(CentreError(aligned->cam_from_world, Rigid3::Identity()), 1e-6);
}

// Something that moved between the views, 3 cm in front of the room's surfaces in the current
// frame only (inside the association gate): on the frame's mask it is not sampled and the motion
// comes out exact; unmasked it pulls the pose.
TEST(AlignDepth, MaskedPixelsAreNotUsed) {
  const PinholeCamera camera = Camera();
  const Rigid3 truth = Rigid3(ExpSO3(Vec3(0.0, 0.01, 0.0)), Vec3(0.02, 0.0, 0.0)).inverse();
  const cv::Mat reference = Render(camera, Rigid3::Identity(), Room());
  cv::Mat current = Render(camera, truth.inverse(), Room());
  cv::Mat mask = cv::Mat::zeros(current.size(), CV_8U);
  const cv::Rect mover(0, 0, 640, 300);
  current(mover) -= 0.03;
  mask(mover).setTo(255);
  const std::optional<DepthAlignment> masked =
      AlignDepth(camera, current, mask, reference, cv::Mat(), Rigid3::Identity(), Rigid3::Identity());
  ASSERT_TRUE(masked.has_value());
  EXPECT_LT(CentreError(masked->cam_from_world, truth), 0.001);
  EXPECT_LT(AngleDeg(masked->cam_from_world, truth), 0.02);
  const std::optional<DepthAlignment> unmasked =
      AlignDepth(camera, current, cv::Mat(), reference, cv::Mat(), Rigid3::Identity(), Rigid3::Identity());
  ASSERT_TRUE(unmasked.has_value());
  EXPECT_GT(CentreError(unmasked->cam_from_world, truth), 0.005);
}

TEST(AlignDepth, TooFewSamplesGiveNothingAndBadInputThrows) {
  const PinholeCamera camera = Camera();
  const cv::Mat empty_depth = cv::Mat::zeros(camera.height(), camera.width(), CV_32F);
  EXPECT_FALSE(AlignDepth(camera, empty_depth, cv::Mat(), empty_depth, cv::Mat(), Rigid3::Identity(), Rigid3::Identity()));
  const cv::Mat wrong_type = cv::Mat::zeros(camera.height(), camera.width(), CV_16U);
  EXPECT_THROW(AlignDepth(camera, wrong_type, cv::Mat(), empty_depth, cv::Mat(), Rigid3::Identity(), Rigid3::Identity()),
               Error);
  DepthAlignmentOptions options;
  options.sample_stride_px = 0;
  EXPECT_THROW(options.Check(), Error);
}

}  // namespace
}  // namespace esdslam
