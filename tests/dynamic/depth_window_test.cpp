// Window depth ranges (direct and block-based) and the motion-dependent window of the check.
#include <gtest/gtest.h>

#include <limits>
#include <random>

#include "common/error.h"
#include "dynamic/depth_window.h"
#include "dynamic/geometry_check.h"
#include "synth/synth_options.h"

namespace esdslam {
namespace {

// Range over the window of `radius` around `pixel`, read pixel by pixel.
bool BruteRange(const cv::Mat& depth, const cv::Point& pixel, int radius, float* near, float* far) {
  *near = std::numeric_limits<float>::infinity();
  *far = 0;
  for (int v = std::max(0, pixel.y - radius); v <= std::min(depth.rows - 1, pixel.y + radius); ++v)
    for (int u = std::max(0, pixel.x - radius); u <= std::min(depth.cols - 1, pixel.x + radius); ++u) {
      const float z = depth.at<float>(v, u);
      if (z > 0) *near = std::min(*near, z), *far = std::max(*far, z);
    }
  return *far > 0;
}

TEST(DepthWindow, BlockRangesContainTheExactWindowAndStayNearIt) {
  cv::Mat depth(120, 160, CV_32F);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> z(0.5f, 5.0f);
  for (int v = 0; v < depth.rows; ++v)
    for (int u = 0; u < depth.cols; ++u) depth.at<float>(v, u) = rng() % 5 == 0 ? 0.f : z(rng);
  depth(cv::Rect(40, 40, 30, 30)).setTo(0.f);  // a hole larger than the windows
  for (const int radius : {1, 3, 6, 13}) {
    const DepthWindow window(depth, radius);
    for (int v = 0; v < depth.rows; v += 7)
      for (int u = 0; u < depth.cols; u += 5) {
        float near, far, exact_near, exact_far, wide_near, wide_far;
        const bool valid = window.Range({u, v}, &near, &far);
        const bool exact = BruteRange(depth, {u, v}, radius, &exact_near, &exact_far);
        const int slack = radius <= DepthWindow::kDirectRadius ? 0 : 2 * DepthWindow::kBlock - 2;
        BruteRange(depth, {u, v}, radius + slack, &wide_near, &wide_far);
        if (exact) {
          ASSERT_TRUE(valid);
          EXPECT_LE(near, exact_near);
          EXPECT_GE(far, exact_far);
        }
        if (valid) {
          EXPECT_GE(near, wide_near);
          EXPECT_LE(far, wide_far);
        }
        if (slack == 0) {
          EXPECT_EQ(valid, exact);
        }
      }
  }
  EXPECT_THROW(DepthWindow(cv::Mat(4, 4, CV_16U), 1), Error);
}

// A wall point just right of a board's edge: measured exactly, it is consistent; with camera
// motion the window grows (colour and depth may be misregistered), the board enters the window,
// and the point is not flagged either; beyond the largest window the frame is not checked.
TEST(GeometryCheck, WindowGrowsWithImageMotionAndFastFramesAreSkipped) {
  const PinholeCamera camera(SynthOptions::DefaultIntrinsics());
  cv::Mat depth(camera.height(), camera.width(), CV_32F, cv::Scalar(3.0f));
  depth(cv::Rect(0, 0, 330, camera.height())).setTo(1.5f);  // board in front, up to u = 329
  ReferenceKeyframe keyframe;
  keyframe.points_world = {camera.Backproject(Vec2(326, 240), 3.0)};  // the keyframe saw the wall at u = 326
  GeometryCheckOptions options;
  GeometryCheckResult still = CheckMultiViewGeometry(camera, Rigid3::Identity(), depth, {keyframe}, options, {}, 0);
  EXPECT_EQ(still.window_radius_px, 1);
  EXPECT_EQ(still.outcomes[0][0], PointOutcome::kCovered);  // looks covered by the board
  GeometryCheckResult moving = CheckMultiViewGeometry(camera, Rigid3::Identity(), depth, {keyframe}, options, {}, 20);
  EXPECT_EQ(moving.window_radius_px, 11);
  EXPECT_EQ(moving.outcomes[0][0], PointOutcome::kConsistent);  // the wall is within reach
  GeometryCheckResult fast = CheckMultiViewGeometry(camera, Rigid3::Identity(), depth, {keyframe}, options, {}, 60);
  EXPECT_TRUE(fast.skipped_fast_motion);
  EXPECT_EQ(fast.num_tested, 0);
  EXPECT_EQ(fast.outcomes[0][0], PointOutcome::kUntested);
  const Rigid3 turned(Quat(Eigen::AngleAxisd(0.01, Vec3::UnitY())), Vec3(0, 0, 0.02));
  EXPECT_NEAR(ImageMotionPx(camera, turned, 2.0), camera.fx() * (0.01 + 0.01), 1e-9);
}

}  // namespace
}  // namespace esdslam
