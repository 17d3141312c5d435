#include "feature/orb_extractor.h"

#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "common/error.h"
#include "feature/descriptor.h"
#include "feature/orb_test_images.h"

namespace esdslam {
namespace {

using test::NoiseTexture;

// Number of keypoints in each cell of a cols x rows grid over the image.
std::vector<int> CellCounts(const std::vector<cv::KeyPoint>& keypoints, cv::Size size, int cols, int rows) {
  std::vector<int> counts(cols * rows, 0);
  for (const auto& kp : keypoints) {
    const int c = std::min(cols - 1, static_cast<int>(kp.pt.x * cols / size.width));
    const int r = std::min(rows - 1, static_cast<int>(kp.pt.y * rows / size.height));
    ++counts[r * cols + c];
  }
  return counts;
}

class OrbExtractorTest : public ::testing::Test {
 protected:
  OrbOptions options_;
  cv::Mat image_ = NoiseTexture(640, 480, 1);
};

TEST_F(OrbExtractorTest, ReturnsTheBudgetSpreadOverTheImage) {
  const OrbExtractor extractor(options_);
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  extractor.Extract(image_, cv::Mat(), &keypoints, &descriptors);
  EXPECT_GE(keypoints.size(), 900u);
  EXPECT_LE(keypoints.size(), 1000u);
  ASSERT_EQ(descriptors.rows, static_cast<int>(keypoints.size()));
  EXPECT_EQ(descriptors.cols, 32);
  EXPECT_EQ(descriptors.type(), CV_8U);
  for (int count : CellCounts(keypoints, image_.size(), 8, 6)) EXPECT_GT(count, 0);
  // Even: no 8x6 cell holds more than 3x its fair share.
  for (int count : CellCounts(keypoints, image_.size(), 8, 6)) EXPECT_LT(count, 3 * 1000 / 48);
  std::vector<int> per_level(extractor.num_levels(), 0);
  for (const auto& kp : keypoints) {
    ASSERT_GE(kp.octave, 0);
    ASSERT_LT(kp.octave, extractor.num_levels());
    ++per_level[kp.octave];
    EXPECT_GE(kp.angle, 0.f);
    EXPECT_LT(kp.angle, 360.f);
    EXPECT_NEAR(kp.size, 31 * extractor.scale_factors()[kp.octave], 1e-3);
    EXPECT_GE(kp.response, options_.min_fast_threshold);
    EXPECT_TRUE(kp.pt.x >= 0 && kp.pt.y >= 0 && kp.pt.x < 640 && kp.pt.y < 480);
  }
  for (int l = 0; l < extractor.num_levels(); ++l) EXPECT_GT(per_level[l], 0) << "level " << l;
}

TEST_F(OrbExtractorTest, IsDeterministic) {
  const OrbExtractor extractor(options_);
  std::vector<cv::KeyPoint> a, b;
  cv::Mat da, db;
  extractor.Extract(image_, cv::Mat(), &a, &da);
  extractor.Extract(image_.clone(), cv::Mat(), &b, &db);
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].pt, b[i].pt);
    EXPECT_EQ(a[i].angle, b[i].angle);
    EXPECT_EQ(a[i].octave, b[i].octave);
  }
  EXPECT_EQ(cv::norm(da, db, cv::NORM_HAMMING), 0);
}

TEST_F(OrbExtractorTest, SpendsTheBudgetOnTheAllowedAreaOfAMask) {
  // People cover 70% of the image: only a 30% vertical band on the right is allowed, plus
  // nothing inside a masked hole within that band.
  cv::Mat mask = cv::Mat::zeros(image_.size(), CV_8U);
  mask(cv::Rect(448, 0, 192, 480)).setTo(255);
  mask(cv::Rect(500, 200, 40, 40)).setTo(0);
  const OrbExtractor extractor(options_);
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  extractor.Extract(image_, mask, &keypoints, &descriptors);
  ASSERT_EQ(descriptors.rows, static_cast<int>(keypoints.size()));
  for (const auto& kp : keypoints) {
    const int u = static_cast<int>(std::lround(kp.pt.x)), v = static_cast<int>(std::lround(kp.pt.y));
    ASSERT_NE(mask.at<unsigned char>(std::min(v, 479), std::min(u, 639)), 0) << kp.pt;
  }
  EXPECT_GE(keypoints.size(), 800u);
  // Spread over the allowed band: every 4x4 cell of the band has keypoints.
  std::vector<cv::KeyPoint> in_band;
  for (auto kp : keypoints) {
    kp.pt.x -= 448;
    in_band.push_back(kp);
  }
  for (int count : CellCounts(in_band, cv::Size(192, 480), 4, 4)) EXPECT_GT(count, 0);
}

TEST_F(OrbExtractorTest, DescriptorsAndAnglesFollowAnImageRotation) {
  // Rotating the image by 90 degrees (exact pixel permutation) must rotate the keypoint angles
  // by 90 degrees and leave descriptors of corresponding level-0 keypoints nearly unchanged.
  cv::Mat square = NoiseTexture(480, 480, 3), rotated;
  cv::rotate(square, rotated, cv::ROTATE_90_CLOCKWISE);  // (x, y) -> (479 - y, x)
  const OrbExtractor extractor(options_);
  std::vector<cv::KeyPoint> kp_a, kp_b;
  cv::Mat d_a, d_b;
  extractor.Extract(square, cv::Mat(), &kp_a, &d_a);
  extractor.Extract(rotated, cv::Mat(), &kp_b, &d_b);
  int pairs = 0, good_descriptor = 0, good_angle = 0;
  for (size_t i = 0; i < kp_a.size(); ++i) {
    if (kp_a[i].octave != 0) continue;
    const cv::Point2f expected(479 - kp_a[i].pt.y, kp_a[i].pt.x);
    for (size_t j = 0; j < kp_b.size(); ++j) {
      if (kp_b[j].octave != 0 || cv::norm(kp_b[j].pt - expected) > 0.1) continue;
      ++pairs;
      good_descriptor += DescriptorDistance(d_a.ptr(static_cast<int>(i)), d_b.ptr(static_cast<int>(j))) < 30;
      const double diff = std::fmod(kp_b[j].angle - kp_a[i].angle + 720.0, 360.0);
      good_angle += std::abs(diff - 90.0) < 2.0;
    }
  }
  ASSERT_GT(pairs, 50);
  EXPECT_GT(good_angle, 0.95 * pairs);
  EXPECT_GT(good_descriptor, 0.8 * pairs);
}

TEST(OrbExtractor, ScaleTablesAndInputChecks) {
  OrbOptions options;
  const OrbExtractor extractor(options);
  ASSERT_EQ(extractor.scale_factors().size(), 8u);
  EXPECT_DOUBLE_EQ(extractor.scale_factors()[0], 1.0);
  EXPECT_NEAR(extractor.scale_factors()[3], 1.728, 1e-12);
  EXPECT_NEAR(extractor.level_sigma2()[2], 1.44 * 1.44, 1e-12);
  EXPECT_NEAR(extractor.inv_level_sigma2()[2] * extractor.level_sigma2()[2], 1.0, 1e-12);
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  EXPECT_THROW(extractor.Extract(cv::Mat(480, 640, CV_8UC3), cv::Mat(), &keypoints, &descriptors), Error);
  EXPECT_THROW(extractor.Extract(cv::Mat(480, 640, CV_8U, cv::Scalar(0)), cv::Mat(10, 10, CV_8U), &keypoints,
                                 &descriptors),
               Error);
  options.num_levels = 0;
  EXPECT_THROW(OrbExtractor{options}, Error);
  // A flat image has no corners; a tiny one has no room for them.
  extractor.Extract(cv::Mat(480, 640, CV_8U, cv::Scalar(128)), cv::Mat(), &keypoints, &descriptors);
  EXPECT_TRUE(keypoints.empty());
  EXPECT_EQ(descriptors.rows, 0);
  extractor.Extract(NoiseTexture(30, 30, 1), cv::Mat(), &keypoints, &descriptors);
  EXPECT_TRUE(keypoints.empty());
}

}  // namespace
}  // namespace esdslam
