#include "dynamic/mask_dilation.h"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

namespace esdslam {
namespace {

cv::Mat Reference(const cv::Mat& mask, int radius) {
  cv::Mat out;
  cv::dilate(mask, out, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * radius + 1, 2 * radius + 1)));
  return out;
}

cv::Mat SmallMask() {
  cv::Mat mask = cv::Mat::zeros(15, 20, CV_8U);
  mask.at<std::uint8_t>(14, 19) = 255;  // a corner: the farthest pixel is the opposite corner
  mask.at<std::uint8_t>(7, 3) = 128;
  return mask;
}

TEST(MaskDilationTest, EqualsOpenCvsEllipticDilationBelowAndAtTheShortcut) {
  const cv::Mat mask = SmallMask();
  for (const int radius : {0, 1, 3, 10, 24, 25, 26, 27, 30}) {
    const cv::Mat expected = radius == 0 ? mask : Reference(mask, radius);
    EXPECT_EQ(cv::countNonZero(DilateEllipse(mask, radius) != expected), 0) << "radius " << radius;
  }
}

// The row-run algorithm against OpenCV's kernel on random masks (values, not only 0/255), near
// the borders, every radius up to 25, and a non-8-bit mask (OpenCV's path).
TEST(MaskDilationTest, EqualsOpenCvOnRandomMasksForEveryRadius) {
  cv::RNG rng(12345);
  for (const cv::Size size : {cv::Size(64, 48), cv::Size(7, 31), cv::Size(640, 3)}) {
    cv::Mat mask = cv::Mat::zeros(size, CV_8U);
    for (int i = 0; i < 12; ++i)
      mask.at<std::uint8_t>(rng.uniform(0, size.height), rng.uniform(0, size.width)) =
          static_cast<std::uint8_t>(rng.uniform(1, 256));
    for (int radius = 1; radius <= 25; ++radius)
      EXPECT_EQ(cv::countNonZero(DilateEllipse(mask, radius) != Reference(mask, radius)), 0)
          << size << " radius " << radius;
  }
  cv::Mat wide = cv::Mat::zeros(20, 30, CV_16U);
  wide.at<std::uint16_t>(10, 12) = 1000;
  EXPECT_EQ(cv::countNonZero(DilateEllipse(wide, 4) != Reference(wide, 4)), 0);
}

// Regression (issue 14): Dynamic.maskDilation: 100000 asked for a 40 GB kernel.
TEST(MaskDilationTest, AHugeRadiusNeedsNoHugeKernel) {
  const cv::Mat mask = SmallMask();
  const cv::Mat out = DilateEllipse(mask, 100000);
  EXPECT_EQ(out.size(), mask.size());
  EXPECT_EQ(cv::countNonZero(out != 255), 0);
  EXPECT_EQ(cv::countNonZero(DilateEllipse(cv::Mat::zeros(480, 640, CV_8U), 100000)), 0);
}

}  // namespace
}  // namespace esdslam
