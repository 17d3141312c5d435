#pragma once
// Labels that come with each frame from the library caller (the public API's label input,
// Semantic.segmenter: provided) instead of a network: the caller's thread puts a frame's label
// image here before the frame is submitted, the segmentation thread takes it by timestamp.
// The class ids index SemanticSettings::onnx.class_names (the caller's class table).

#include <map>
#include <memory>
#include <mutex>
#include <string>

#include <opencv2/core.hpp>

#include "semantic/segmenter.h"

namespace esdslam {

// Frames' label images by timestamp. Thread-safe.
class ProvidedLabels {
 public:
  // labels: CV_8UC1 class ids. Throws Error on another type.
  void Put(double timestamp, const cv::Mat& labels);
  // The labels of `timestamp` (removed from the store), or an empty Mat when none were put.
  cv::Mat Take(double timestamp);
  std::size_t size() const;

 private:
  mutable std::mutex mutex_;
  std::map<double, cv::Mat> by_timestamp_;
};

// A Segmenter that returns the labels put for the frame. Throws Error naming the frame when none
// were put, or when their size differs from the image's.
class ProvidedLabelsSegmenter final : public Segmenter {
 public:
  explicit ProvidedLabelsSegmenter(std::shared_ptr<ProvidedLabels> labels) : labels_(std::move(labels)) {}
  SegmentationResult Segment(const cv::Mat& bgr, double timestamp) override;
  std::string Name() const override { return "provided"; }

 private:
  std::shared_ptr<ProvidedLabels> labels_;
};

}  // namespace esdslam
