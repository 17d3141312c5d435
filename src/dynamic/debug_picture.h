#pragma once
// A picture of what dynamic-object handling did to one frame (`esdslam run --debug-frames`):
// the colour image with the refined semantic mask tinted cyan and the geometry check's mask
// tinted magenta (both outlined), and every keypoint as a circle: kept green, removed by the
// mask red, removed by the geometry check magenta; a legend with the three counts.

#include <opencv2/core.hpp>

#include "map/feature_set.h"

namespace esdslam {

// bgr: CV_8UC3 (not changed; the picture is a copy). semantic_mask, geometry_mask: CV_8U,
// nonzero = masked, or empty. features: the frame's keypoints (raw pixels) and is_dynamic flags.
cv::Mat DrawDynamicDebugPicture(const cv::Mat& bgr, const cv::Mat& semantic_mask, const cv::Mat& geometry_mask,
                                const FeatureSet& features);

}  // namespace esdslam
