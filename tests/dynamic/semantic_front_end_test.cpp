// Real-time hand-off: carrying an older frame's dynamic mask to the current frame.
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "dynamic/semantic_front_end.h"

namespace esdslam {
namespace {

PinholeCamera TestCamera() {
  CameraIntrinsics intrinsics;
  intrinsics.fx = intrinsics.fy = 500;
  intrinsics.cx = 320, intrinsics.cy = 240;
  intrinsics.width = 640, intrinsics.height = 480;
  return PinholeCamera(intrinsics);
}

cv::Rect Bounds(const cv::Mat& mask) { return cv::boundingRect(mask); }

TEST(WarpMaskTest, SidewaysMotionShiftsByFocalTimesBaselineOverDepth) {
  cv::Mat mask = cv::Mat::zeros(480, 640, CV_8U);
  mask(cv::Rect(200, 150, 80, 160)).setTo(255);
  const cv::Mat depth(480, 640, CV_32F, cv::Scalar(2.0f));
  // Camera b is 0.1 m to the right of a: points move 500 * 0.1 / 2 = 25 px to the left.
  const Rigid3 b_from_a(Mat3::Identity(), Vec3(-0.1, 0, 0));
  const cv::Mat warped = WarpMask(mask, depth, b_from_a, TestCamera(), 0);
  const cv::Rect box = Bounds(warped);
  EXPECT_NEAR(box.x, 175, 1);
  EXPECT_NEAR(box.width, 80, 2);
  EXPECT_NEAR(box.y, 150, 1);
  EXPECT_NEAR(cv::countNonZero(warped), 80 * 160, 80 * 160 * 0.03);  // no holes
}

TEST(WarpMaskTest, PixelsWithoutDepthStayAndDilationGrows) {
  cv::Mat mask = cv::Mat::zeros(480, 640, CV_8U);
  mask(cv::Rect(300, 200, 20, 20)).setTo(255);
  const cv::Mat no_depth = cv::Mat::zeros(480, 640, CV_32F);
  const Rigid3 b_from_a(Mat3::Identity(), Vec3(-0.5, 0, 0));
  const cv::Mat warped = WarpMask(mask, no_depth, b_from_a, TestCamera(), 3);
  EXPECT_EQ(Bounds(warped), cv::Rect(297, 197, 26, 26));
}

TEST(WarpMaskTest, ForwardMotionMagnifiesWithoutHoles) {
  cv::Mat mask = cv::Mat::zeros(480, 640, CV_8U);
  mask(cv::Rect(280, 200, 80, 80)).setTo(255);
  const cv::Mat depth(480, 640, CV_32F, cv::Scalar(2.0f));
  const Rigid3 b_from_a(Mat3::Identity(), Vec3(0, 0, -0.2));  // 0.2 m closer: scale 2 / 1.8
  const cv::Mat warped = WarpMask(mask, depth, b_from_a, TestCamera(), 0);
  const double scale = 2.0 / 1.8;
  EXPECT_NEAR(Bounds(warped).width, 80 * scale, 2);
  EXPECT_NEAR(cv::countNonZero(warped), 80 * 80 * scale * scale, 80 * 80 * 0.05);
}

}  // namespace
}  // namespace esdslam
