// The debug picture of a frame: masks tinted, keypoints drawn in the colour of their flag.
#include <gtest/gtest.h>

#include "dynamic/debug_picture.h"

namespace esdslam {
namespace {

cv::Vec3b At(const cv::Mat& picture, int x, int y) { return picture.at<cv::Vec3b>(y, x); }

// Whether the 9 x 9 pixels around (x, y) hold `colour` (the circles are antialiased: within 60
// of it, summed over the channels).
bool DrawnAround(const cv::Mat& picture, int x, int y, const cv::Vec3b& colour) {
  for (int v = y - 4; v <= y + 4; ++v)
    for (int u = x - 4; u <= x + 4; ++u)
      if (cv::norm(cv::Vec3i(At(picture, u, v)) - cv::Vec3i(colour), cv::NORM_L1) < 60) return true;
  return false;
}

TEST(DebugPictureTest, TintsMasksAndColoursKeypointsByFlag) {
  const cv::Mat bgr(120, 160, CV_8UC3, cv::Scalar(100, 100, 100));
  cv::Mat semantic = cv::Mat::zeros(bgr.size(), CV_8U), geometry = cv::Mat::zeros(bgr.size(), CV_8U);
  semantic(cv::Rect(10, 40, 30, 30)).setTo(255);
  geometry(cv::Rect(110, 40, 30, 30)).setTo(255);
  FeatureSet features;
  for (const float x : {60.f, 80.f, 100.f}) features.keypoints.emplace_back(cv::Point2f(x, 100.f), 7.f);
  features.is_dynamic = {0, kDynamicByMask, kDynamicByGeometry};
  const cv::Mat picture = DrawDynamicDebugPicture(bgr, semantic, geometry, features);
  ASSERT_EQ(picture.size(), bgr.size());
  EXPECT_EQ(At(bgr, 25, 55), cv::Vec3b(100, 100, 100));  // the input is not drawn on
  // Mask interiors blended 35 % with cyan (255, 255, 0) and magenta (255, 0, 255), BGR order.
  EXPECT_EQ(At(picture, 25, 55), cv::Vec3b(154, 154, 65));
  EXPECT_EQ(At(picture, 125, 55), cv::Vec3b(154, 65, 154));
  EXPECT_EQ(At(picture, 80, 40), cv::Vec3b(100, 100, 100));  // untouched elsewhere
  EXPECT_EQ(At(picture, 80, 100), cv::Vec3b(100, 100, 100));  // a circle's centre
  // A circle of radius 3 around each keypoint: kept green, by the mask red, by geometry magenta.
  const cv::Vec3b green(0, 255, 0), red(0, 0, 255), magenta(255, 0, 255);
  EXPECT_TRUE(DrawnAround(picture, 60, 100, green));
  EXPECT_FALSE(DrawnAround(picture, 60, 100, red));
  EXPECT_TRUE(DrawnAround(picture, 80, 100, red));
  EXPECT_TRUE(DrawnAround(picture, 100, 100, magenta));
  EXPECT_FALSE(DrawnAround(picture, 100, 100, green));
}

TEST(DebugPictureTest, EmptyMasksAndNoKeypoints) {
  const cv::Mat bgr(60, 400, CV_8UC3, cv::Scalar(100, 100, 100));
  const cv::Mat picture = DrawDynamicDebugPicture(bgr, cv::Mat(), cv::Mat(), FeatureSet{});
  EXPECT_EQ(At(picture, 200, 50), cv::Vec3b(100, 100, 100));
  EXPECT_GT(cv::norm(picture, bgr, cv::NORM_L1), 0);  // the legend
}

}  // namespace
}  // namespace esdslam
