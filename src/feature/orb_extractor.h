#pragma once
// ORB feature extraction as ORB-SLAM2 does it: a scale pyramid, FAST corners detected per cell
// (with a fallback threshold in cells without corners), an even spatial distribution by quadtree
// per level, intensity-centroid orientation and rotated BRIEF (256 bit) descriptors.

#include <vector>

#include <opencv2/core.hpp>

#include "feature/orb_options.h"

namespace esdslam {

class OrbExtractor {
 public:
  explicit OrbExtractor(const OrbOptions& options);

  // gray: CV_8UC1. mask: empty, or CV_8UC1 of the same size, nonzero = keypoints allowed there
  // (the whole budget is then spent on the allowed area).
  // Output keypoints are in level-0 raw (distorted) pixel coordinates; octave = pyramid level,
  // angle in degrees [0, 360), size = patch diameter at level 0 scale, response = FAST score.
  // descriptors: N x 32 CV_8U, row i for keypoint i. Deterministic. Thread-safe (const).
  void Extract(const cv::Mat& gray, const cv::Mat& mask, std::vector<cv::KeyPoint>* keypoints,
               cv::Mat* descriptors) const;

  const OrbOptions& options() const { return options_; }
  int num_levels() const { return options_.num_levels; }
  const std::vector<double>& scale_factors() const { return scale_factors_; }  // level 0 = 1
  const std::vector<double>& inv_scale_factors() const { return inv_scale_factors_; }
  const std::vector<double>& level_sigma2() const { return level_sigma2_; }  // scale^2
  const std::vector<double>& inv_level_sigma2() const { return inv_level_sigma2_; }
  // Keypoint budget per level for an unmasked image (sums to num_features).
  const std::vector<int>& features_per_level() const { return features_per_level_; }

 private:
  OrbOptions options_;
  std::vector<double> scale_factors_, inv_scale_factors_, level_sigma2_, inv_level_sigma2_;
  std::vector<int> features_per_level_;
};

}  // namespace esdslam
