#pragma once
// Smallest and largest valid depth within a square window (2r+1)^2 around a pixel, for many
// queries on one depth image (the geometry check's measured-depth test). Radii up to
// kDirectRadius read the window directly. Larger radii (fast camera motion) use per-block
// minima and maxima (kBlock x kBlock blocks) spread over the window once per image, so a query
// costs O(1); that window is rounded up to whole blocks (at most kBlock - 1 px larger per side).

#include <opencv2/core.hpp>

namespace esdslam {

class DepthWindow {
 public:
  static constexpr int kDirectRadius = 3;
  static constexpr int kBlock = 4;

  // depth_m: CV_32F metres, 0 = invalid (kept by reference). radius_px >= 0.
  DepthWindow(const cv::Mat& depth_m, int radius_px);

  // False when no valid depth lies in the window (near, far undefined then).
  bool Range(const cv::Point& pixel, float* near, float* far) const;
  int radius() const { return radius_; }

 private:
  const cv::Mat& depth_m_;
  int radius_;
  cv::Mat block_near_, block_far_;  // CV_32F per block, spread over the window (+inf / 0 = none)
};

}  // namespace esdslam
