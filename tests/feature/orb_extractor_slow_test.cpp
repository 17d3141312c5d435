// ORB extraction on every frame of the real dev sequences (../shared/data).
#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/features2d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "feature/orb_extractor.h"

namespace esdslam {
namespace {

std::vector<std::string> FramePaths(const std::string& sequence) {
  const std::filesystem::path dir = std::filesystem::path(ESDSLAM_TEST_DATA_DIR) / "data" / sequence / "rgb";
  std::vector<std::string> paths;
  if (!std::filesystem::is_directory(dir)) return paths;
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    if (entry.path().extension() == ".png") paths.push_back(entry.path().string());
  std::sort(paths.begin(), paths.end());
  return paths;
}

// 4x4 grid cell of a level-0 point in a 640x480-like image.
int Cell(const cv::Point2f& p, cv::Size size) {
  const int col = std::min(3, static_cast<int>(p.x * 4 / size.width));
  const int row = std::min(3, static_cast<int>(p.y * 4 / size.height));
  return row * 4 + col;
}

// Every frame: ~num_features keypoints, and every 4x4 cell that is textured (>= 20 FAST corners
// at the minimum threshold away from the 19 px border where no keypoint may lie) gets keypoints.
void CheckSequence(const std::string& sequence, int expected_frames) {
  const std::vector<std::string> paths = FramePaths(sequence);
  if (paths.empty()) GTEST_SKIP() << "no data for " << sequence << " under " << ESDSLAM_TEST_DATA_DIR;
  ASSERT_EQ(static_cast<int>(paths.size()), expected_frames);
  const OrbOptions options;
  const OrbExtractor extractor(options);
  int frames_with_all_cells = 0;
  for (const std::string& path : paths) {
    cv::Mat gray;
    cv::cvtColor(cv::imread(path, cv::IMREAD_COLOR), gray, cv::COLOR_BGR2GRAY);
    std::vector<cv::KeyPoint> keypoints, fast;
    cv::Mat descriptors;
    extractor.Extract(gray, cv::Mat(), &keypoints, &descriptors);
    EXPECT_GE(keypoints.size(), 0.9 * options.num_features) << path;
    EXPECT_LE(keypoints.size(), static_cast<size_t>(options.num_features)) << path;
    cv::FAST(gray, fast, options.min_fast_threshold, true);
    int corners[16] = {0}, kept[16] = {0};
    for (const auto& kp : fast)
      if (kp.pt.x >= 19 && kp.pt.y >= 19 && kp.pt.x < gray.cols - 19 && kp.pt.y < gray.rows - 19)
        ++corners[Cell(kp.pt, gray.size())];
    for (const auto& kp : keypoints) ++kept[Cell(kp.pt, gray.size())];
    bool all = true;
    for (int c = 0; c < 16; ++c) {
      if (corners[c] >= 20) {
        EXPECT_GT(kept[c], 0) << path << " cell " << c << " has " << corners[c] << " corners";
      }
      all = all && kept[c] > 0;
    }
    frames_with_all_cells += all;
  }
  // Most frames have keypoints in all 16 cells (the rest have a textureless cell).
  EXPECT_GT(frames_with_all_cells, 0.3 * expected_frames);
}

TEST(OrbExtractorSlow, CoversEveryTexturedCellOfTumRpyFrames) { CheckSequence("tum_fr1_rpy_dev", 120); }
TEST(OrbExtractorSlow, CoversEveryTexturedCellOfBonnCrowdFrames) { CheckSequence("bonn_crowd_dev", 250); }

}  // namespace
}  // namespace esdslam
