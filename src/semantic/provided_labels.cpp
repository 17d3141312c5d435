#include "semantic/provided_labels.h"

#include <fmt/format.h>

#include "common/error.h"

namespace esdslam {

void ProvidedLabels::Put(double timestamp, const cv::Mat& labels) {
  if (labels.type() != CV_8UC1)
    throw Error(fmt::format("frame {:.6f}: labels must be CV_8UC1 class ids, got OpenCV type {}", timestamp,
                            labels.type()));
  std::lock_guard<std::mutex> lock(mutex_);
  by_timestamp_[timestamp] = labels;
}

cv::Mat ProvidedLabels::Take(double timestamp) {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto it = by_timestamp_.find(timestamp);
  if (it == by_timestamp_.end()) return cv::Mat();
  cv::Mat labels = it->second;
  by_timestamp_.erase(it);
  return labels;
}

std::size_t ProvidedLabels::size() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return by_timestamp_.size();
}

SegmentationResult ProvidedLabelsSegmenter::Segment(const cv::Mat& bgr, double timestamp) {
  SegmentationResult result;
  result.labels = labels_->Take(timestamp);
  if (result.labels.empty())
    throw Error(fmt::format("frame {:.6f}: no labels were given with the frame (Semantic.segmenter: provided "
                            "takes each frame's label image from the caller)",
                            timestamp));
  if (result.labels.size() != bgr.size())
    throw Error(fmt::format("frame {:.6f}: labels are {}x{}, the image {}x{}", timestamp, result.labels.cols,
                            result.labels.rows, bgr.cols, bgr.rows));
  return result;
}

}  // namespace esdslam
