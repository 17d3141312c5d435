#include "semantic/score_upsampling.h"

#include <gtest/gtest.h>

#include "common/error.h"

namespace esdslam {
namespace {

cv::Mat Blob(int classes, int rows, int cols) {
  cv::Mat blob(std::vector<int>{1, classes, rows, cols}, CV_32F);
  float* v = blob.ptr<float>();
  for (int i = 0; i < classes * rows * cols; ++i) v[i] = static_cast<float>(i);
  return blob;
}

TEST(UpsampleAlignCorners, CornersAreKeptAndMidpointsAveraged) {
  // Class 0: [[0, 1], [2, 3]]; class 1: the same + 4. 3x3 output: the corners stay, the rest
  // sample at half steps.
  const std::vector<cv::Mat> planes = UpsampleAlignCorners(Blob(2, 2, 2), cv::Size(3, 3));
  ASSERT_EQ(planes.size(), 2u);
  const float expected[3][3] = {{0, 0.5f, 1}, {1, 1.5f, 2}, {2, 2.5f, 3}};
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 3; ++x) {
      EXPECT_FLOAT_EQ(planes[0].at<float>(y, x), expected[y][x]) << x << "," << y;
      EXPECT_FLOAT_EQ(planes[1].at<float>(y, x), expected[y][x] + 4) << x << "," << y;
    }
}

TEST(UpsampleAlignCorners, MatchesTheDefinitionOnAnUnevenScale) {
  // 3x4 -> 8x9: output (x, y) samples the input at (x * 3 / 8, y * 2 / 7); the input is linear in
  // both axes (value = 4 row + col), so the bilinear result is that linear function.
  const std::vector<cv::Mat> planes = UpsampleAlignCorners(Blob(1, 3, 4), cv::Size(9, 8));
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 9; ++x)
      EXPECT_NEAR(planes[0].at<float>(y, x), 4.0 * y * 2.0 / 7.0 + x * 3.0 / 8.0, 1e-5) << x << "," << y;
}

TEST(UpsampleAlignCorners, SingleOutputPixelSamplesTheFirstInput) {
  const std::vector<cv::Mat> planes = UpsampleAlignCorners(Blob(1, 2, 2), cv::Size(1, 1));
  EXPECT_FLOAT_EQ(planes[0].at<float>(0, 0), 0.0f);
}

TEST(UpsampleAlignCorners, RejectsOtherShapes) {
  EXPECT_THROW(UpsampleAlignCorners(cv::Mat(4, 4, CV_32F), cv::Size(8, 8)), Error);
  EXPECT_THROW(UpsampleAlignCorners(Blob(1, 2, 2), cv::Size(0, 3)), Error);
  cv::Mat wrong_type(std::vector<int>{1, 1, 2, 2}, CV_8U);
  EXPECT_THROW(UpsampleAlignCorners(wrong_type, cv::Size(3, 3)), Error);
}

}  // namespace
}  // namespace esdslam
