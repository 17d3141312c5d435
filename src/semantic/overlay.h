#pragma once
// Colour overlays of label images for inspection (PASCAL VOC palette).

#include <opencv2/core.hpp>

namespace esdslam {

// The PASCAL VOC palette colour of a class id, as BGR.
cv::Vec3b VocColorBgr(int class_id);

// `bgr` with every non-background pixel blended with its class colour (weight `alpha` in
// [0,1]) and class borders drawn in the full colour. labels: CV_8UC1 of the same size.
cv::Mat DrawLabelOverlay(const cv::Mat& bgr, const cv::Mat& labels, double alpha = 0.5);

}  // namespace esdslam
