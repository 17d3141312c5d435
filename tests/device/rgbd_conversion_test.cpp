// The driver-independent conversions of a camera source: millimetre depth to metres, RGB888 to
// BGR (padded rows too), and software depth registration against hand-computed projections.
#include <cstdint>
#include <vector>

#include <gtest/gtest.h>

#include "common/error.h"
#include "device/rgbd_conversion.h"

namespace esdslam {
namespace {

TEST(RgbdConversionTest, DepthMillimetresBecomeMetresAndZeroStaysInvalid) {
  // 3x2 image in rows of 4 values (one value of padding per row).
  const std::vector<std::uint16_t> mm = {0, 1000, 1234, 9, 65535, 1, 500, 9};
  const cv::Mat m = DepthMmToMetres(mm.data(), 3, 2, 4 * sizeof(std::uint16_t));
  ASSERT_EQ(m.type(), CV_32F);
  ASSERT_EQ(m.size(), cv::Size(3, 2));
  EXPECT_EQ(m.at<float>(0, 0), 0.0f);
  EXPECT_FLOAT_EQ(m.at<float>(0, 1), 1.0f);
  EXPECT_FLOAT_EQ(m.at<float>(0, 2), 1.234f);
  EXPECT_FLOAT_EQ(m.at<float>(1, 0), 65.535f);
  EXPECT_FLOAT_EQ(m.at<float>(1, 1), 0.001f);
  EXPECT_FLOAT_EQ(m.at<float>(1, 2), 0.5f);
  EXPECT_NE(m.data, reinterpret_cast<const uchar*>(mm.data()));  // our own copy, the driver's buffer is reused
  EXPECT_THROW(DepthMmToMetres(nullptr, 3, 2, 8), Error);
  EXPECT_THROW(DepthMmToMetres(mm.data(), 3, 2, 4), Error);  // stride shorter than a row
}

TEST(RgbdConversionTest, Rgb888BecomesBgrRowByRow) {
  // 2x2 pixels, rows of 7 bytes (6 + 1 padding): red, green / blue, (10, 20, 30).
  const std::vector<std::uint8_t> rgb = {255, 0, 0, 0, 255, 0, 77, 0, 0, 255, 10, 20, 30, 77};
  const cv::Mat bgr = Rgb888ToBgr(rgb.data(), 2, 2, 7);
  ASSERT_EQ(bgr.type(), CV_8UC3);
  EXPECT_EQ(bgr.at<cv::Vec3b>(0, 0), cv::Vec3b(0, 0, 255));  // red in BGR
  EXPECT_EQ(bgr.at<cv::Vec3b>(0, 1), cv::Vec3b(0, 255, 0));
  EXPECT_EQ(bgr.at<cv::Vec3b>(1, 0), cv::Vec3b(255, 0, 0));  // blue
  EXPECT_EQ(bgr.at<cv::Vec3b>(1, 1), cv::Vec3b(30, 20, 10));
  EXPECT_THROW(Rgb888ToBgr(rgb.data(), 0, 2, 7), Error);
}

CameraIntrinsics Camera(int width, int height, double f, double cx, double cy) {
  CameraIntrinsics camera;
  camera.width = width;
  camera.height = height;
  camera.fx = camera.fy = f;
  camera.cx = cx;
  camera.cy = cy;
  return camera;
}

TEST(RgbdConversionTest, SameCameraAndNoOffsetLeaveDepthWhereItIs) {
  const CameraIntrinsics camera = Camera(8, 6, 10, 4, 3);
  cv::Mat depth(6, 8, CV_32F, cv::Scalar(0));
  depth.at<float>(1, 2) = 2.0f;
  depth.at<float>(4, 6) = 0.75f;
  const cv::Mat registered = RegisterDepthToColour(depth, camera, camera, Rigid3::Identity());
  EXPECT_EQ(cv::countNonZero(registered != depth), 0);
}

TEST(RgbdConversionTest, DepthMovesByTheBaselineAndTheColourCamerasModel) {
  const CameraIntrinsics depth_camera = Camera(20, 10, 10, 10, 5);
  const CameraIntrinsics colour_camera = Camera(40, 20, 20, 20, 10);  // twice the resolution
  // Colour camera 0.25 m to the right of the depth camera: points move 0.25 m left in it.
  const Rigid3 colour_from_depth(Mat3::Identity(), Vec3(-0.25, 0, 0));
  cv::Mat depth(10, 20, CV_32F, cv::Scalar(0));
  depth.at<float>(5, 10) = 1.0f;  // on the depth camera's axis, 1 m away: (0, 0, 1)
  depth.at<float>(5, 15) = 2.0f;  // (1, 0, 2)
  const cv::Mat registered = RegisterDepthToColour(depth, depth_camera, colour_camera, colour_from_depth);
  ASSERT_EQ(registered.size(), cv::Size(40, 20));
  // (0,0,1) -> (-0.25, 0, 1): u = 20 * -0.25 + 20 = 15. (1,0,2) -> (0.75, 0, 2): u = 20 * 0.375 + 20 = 27.5 -> 28.
  EXPECT_FLOAT_EQ(registered.at<float>(10, 15), 1.0f);
  EXPECT_FLOAT_EQ(registered.at<float>(10, 28), 2.0f);
  EXPECT_EQ(cv::countNonZero(registered), 2);
}

TEST(RgbdConversionTest, TheNearestSurfaceWinsAndBadInputIsRefused) {
  const CameraIntrinsics camera = Camera(4, 1, 2, 2, 0);
  // Two depth pixels land on colour pixel 1 after a 0.5 m move (std::lround: 0.5 -> 1).
  cv::Mat depth(1, 4, CV_32F, cv::Scalar(0));
  depth.at<float>(0, 1) = 2.0f;  // x = (1 - 2) * 2 / 2 = -1 -> -1.5 after the move: u = 2 * -1.5 / 2 + 2 = 0.5 -> 1
  depth.at<float>(0, 2) = 1.0f;  // x = 0 -> -0.5: u = 2 * -0.5 / 1 + 2 = 1
  const cv::Mat registered = RegisterDepthToColour(depth, camera, camera, Rigid3(Mat3::Identity(), Vec3(-0.5, 0, 0)));
  EXPECT_FLOAT_EQ(registered.at<float>(0, 1), 1.0f);
  EXPECT_THROW(RegisterDepthToColour(cv::Mat(2, 2, CV_32F), camera, camera, Rigid3::Identity()), Error);
  EXPECT_THROW(RegisterDepthToColour(cv::Mat(1, 4, CV_16U), camera, camera, Rigid3::Identity()), Error);
}

}  // namespace
}  // namespace esdslam
