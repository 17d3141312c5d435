#pragma once
// Binary (ORB) descriptor helpers.

#include <opencv2/core.hpp>

namespace esdslam {

// Matching thresholds on the Hamming distance (ORB-SLAM2's TH_HIGH / TH_LOW).
constexpr int kDescriptorDistanceHigh = 100;
constexpr int kDescriptorDistanceLow = 50;

// Hamming distance over 256 bits between two descriptor rows (1 x 32 CV_8U each, continuous).
int DescriptorDistance(const cv::Mat& a, const cv::Mat& b);
// Same, on raw 32-byte buffers.
int DescriptorDistance(const unsigned char* a, const unsigned char* b);

}  // namespace esdslam
