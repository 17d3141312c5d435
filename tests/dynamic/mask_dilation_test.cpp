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
