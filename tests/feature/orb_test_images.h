#pragma once
// Test images for the ORB extractor tests.

#include <random>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

namespace esdslam::test {

// Multi-scale smoothed noise texture (deterministic): corners at every pyramid level.
inline cv::Mat NoiseTexture(int width, int height, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> noise(0.f, 1.f);
  cv::Mat texture = cv::Mat::zeros(height, width, CV_32F);
  for (const int step : {2, 6, 20}) {
    cv::Mat coarse(height / step + 2, width / step + 2, CV_32F);
    for (int r = 0; r < coarse.rows; ++r)
      for (int c = 0; c < coarse.cols; ++c) coarse.at<float>(r, c) = noise(rng);
    cv::Mat fine;
    cv::resize(coarse, fine, cv::Size(coarse.cols * step, coarse.rows * step), 0, 0, cv::INTER_CUBIC);
    texture += fine(cv::Rect(0, 0, width, height));
  }
  cv::Mat gray;
  cv::normalize(texture, texture, 0, 255, cv::NORM_MINMAX);
  texture.convertTo(gray, CV_8U);
  return gray;
}

}  // namespace esdslam::test
