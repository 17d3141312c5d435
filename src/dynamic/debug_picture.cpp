#include "dynamic/debug_picture.h"

#include <string>
#include <vector>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

namespace esdslam {
namespace {

void Tint(cv::Mat& picture, const cv::Mat& mask, const cv::Scalar& colour) {
  if (mask.empty() || cv::countNonZero(mask) == 0) return;
  cv::Mat blended;
  cv::addWeighted(picture, 0.65, cv::Mat(picture.size(), picture.type(), colour), 0.35, 0, blended);
  blended.copyTo(picture, mask);
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(mask.clone(), contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_SIMPLE);
  cv::drawContours(picture, contours, -1, colour, 2);
}

}  // namespace

cv::Mat DrawDynamicDebugPicture(const cv::Mat& bgr, const cv::Mat& semantic_mask, const cv::Mat& geometry_mask,
                                const FeatureSet& features) {
  const cv::Scalar cyan(255, 255, 0), magenta(255, 0, 255), red(0, 0, 255), green(0, 255, 0);
  cv::Mat picture = bgr.clone();
  Tint(picture, semantic_mask, cyan);
  Tint(picture, geometry_mask, magenta);
  int by_mask = 0, by_geometry = 0;
  for (int k = 0; k < features.size(); ++k) {
    const std::uint8_t flag = features.is_dynamic[k];
    by_geometry += flag == kDynamicByGeometry;
    by_mask += flag != 0 && flag != kDynamicByGeometry;
    const cv::Scalar colour = flag == kDynamicByGeometry ? magenta : flag != 0 ? red : green;
    cv::circle(picture, features.keypoints[k].pt, 3, colour, 1, cv::LINE_AA);
  }
  const std::string legend = fmt::format("{} kept (green), {} mask (red), {} geometry (magenta)",
                                         features.size() - by_mask - by_geometry, by_mask, by_geometry);
  cv::putText(picture, legend, cv::Point(8, 18), cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(0, 0, 0), 3, cv::LINE_AA);
  cv::putText(picture, legend, cv::Point(8, 18), cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(255, 255, 255), 1,
              cv::LINE_AA);
  return picture;
}

}  // namespace esdslam
