#pragma once
// The shipped ESPNetv2 model loaded with and without this project's OpenCV DNN layers, and the
// comparison of two segmenters' scores, for the semantic stage's layer tests (compiled into the
// semantic tests only: tests/CMakeLists.txt).
#include <string>

#include <opencv2/core.hpp>

#include "semantic/onnx_segmenter.h"

namespace esdslam::testing {

// models/espnetv2_s2.0_voc_256x192.onnx at 256x192; the flags are OnnxSegmenterOptions's.
OnnxSegmenter ShippedSegmenter(bool separable_resize, bool own_layers);

// Both segmenters on `bgr` (gtest expectations, `what` names the image): scores within 1e-4 of
// the largest score magnitude, the same argmax on >= 99.9 % of the pixels. Prints both measures.
void ExpectSameScores(OnnxSegmenter& ours, OnnxSegmenter& reference, const cv::Mat& bgr, const std::string& what);

// ExpectSameScores on the first, middle and last PNG of ../shared/data/bonn_crowd_dev/rgb; skips
// the test (GTEST_SKIP) when that folder is missing.
void ExpectSameScoresOnBonnFrames(OnnxSegmenter& ours, OnnxSegmenter& reference);

}  // namespace esdslam::testing
