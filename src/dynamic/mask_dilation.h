#pragma once
// Elliptic dilation whose cost a setting cannot blow up: a radius that reaches past the image's
// diagonal gives the image's maximum everywhere (what the dilation gives then), computed without
// building the (2r+1)^2 kernel, so e.g. Dynamic.maskDilation: 100000 needs no 40 GB.

#include <cmath>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

namespace esdslam {

// mask: single channel; radius_px <= 0 returns it unchanged.
inline cv::Mat DilateEllipse(const cv::Mat& mask, int radius_px) {
  if (radius_px <= 0 || mask.empty()) return mask;
  // Every offset inside the image lies within the ellipse (+2 px for the kernel's rounding).
  if (radius_px >= std::hypot(mask.cols, mask.rows) + 2) {
    double max_value = 0;
    cv::minMaxLoc(mask, nullptr, &max_value);
    return cv::Mat(mask.size(), mask.type(), cv::Scalar(max_value));
  }
  cv::Mat out;
  cv::dilate(mask, out, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * radius_px + 1, 2 * radius_px + 1)));
  return out;
}

}  // namespace esdslam
