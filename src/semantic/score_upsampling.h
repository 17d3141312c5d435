#pragma once
// Bilinear upsampling of a network's class-score blob with aligned corners: the ONNX Resize of
// mode "linear" with coordinate_transformation_mode "align_corners", the last layer of the
// ESPNetv2 decoder (2x, to the network input size). OpenCV DNN's Resize layer computes it one
// pixel at a time (about a tenth of the network's time at 256x192); OnnxSegmenter takes the scores
// before that layer and upsamples them here, separably (rows, then columns), with the same
// result up to float rounding.
//
// Output pixel (x, y) samples the input at (x (w - 1) / (W - 1), y (h - 1) / (H - 1)) (0 when the
// output has one pixel along that axis), bilinear between the four neighbours.

#include <vector>

#include <opencv2/core.hpp>

namespace esdslam {

// scores: CV_32F blob 1 x C x h x w (contiguous). Returns C CV_32FC1 planes of out_size.
// Throws Error on another shape or type, or an empty out_size.
std::vector<cv::Mat> UpsampleAlignCorners(const cv::Mat& scores, cv::Size out_size);

}  // namespace esdslam
