#include "support/shipped_segmenter.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "support/test_paths.h"

namespace esdslam::testing {
namespace fs = std::filesystem;

OnnxSegmenter ShippedSegmenter(bool separable_resize, bool own_layers) {
  OnnxSegmenterOptions o;
  o.model_path = SourceDir() + "/models/espnetv2_s2.0_voc_256x192.onnx";
  o.input_width = 256;
  o.input_height = 192;
  o.separable_resize = separable_resize;
  o.own_layers = own_layers;
  return OnnxSegmenter(o);
}

void ExpectSameScores(OnnxSegmenter& ours, OnnxSegmenter& reference, const cv::Mat& bgr, const std::string& what) {
  const std::vector<cv::Mat> mine = ours.Scores(bgr), theirs = reference.Scores(bgr);
  ASSERT_EQ(mine.size(), theirs.size());
  double largest_error = 0, largest_score = 0;
  for (std::size_t c = 0; c < mine.size(); ++c) {
    largest_error = std::max(largest_error, cv::norm(mine[c], theirs[c], cv::NORM_INF));
    largest_score = std::max(largest_score, cv::norm(theirs[c], cv::NORM_INF));
  }
  const cv::Mat labels = ArgmaxLabels(mine), reference_labels = ArgmaxLabels(theirs);
  const double agreement = cv::countNonZero(labels == reference_labels) / static_cast<double>(labels.total());
  std::printf("%s: largest score difference %.3g (largest score %.3g), labels agree on %.4f%%\n", what.c_str(),
              largest_error, largest_score, 100.0 * agreement);
  EXPECT_LE(largest_error, 1e-4 * largest_score) << what;
  EXPECT_GE(agreement, 0.999) << what;
}

void ExpectSameScoresOnBonnFrames(OnnxSegmenter& ours, OnnxSegmenter& reference) {
  const fs::path rgb = fs::path(TestDataDir()) / "data" / "bonn_crowd_dev" / "rgb";
  if (!fs::is_directory(rgb)) GTEST_SKIP() << "no Bonn frames at " << rgb;
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(rgb))
    if (entry.path().extension() == ".png") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  ASSERT_FALSE(files.empty());
  for (std::size_t i : {std::size_t{0}, files.size() / 2, files.size() - 1}) {  // first, middle, last
    const cv::Mat bgr = cv::imread(files[i].string(), cv::IMREAD_COLOR);
    ASSERT_FALSE(bgr.empty()) << files[i];
    ExpectSameScores(ours, reference, bgr, files[i].filename().string());
  }
}

}  // namespace esdslam::testing
