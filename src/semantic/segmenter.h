#pragma once
// Semantic segmentation interface. A segmenter labels every pixel of a BGR frame with a PASCAL
// VOC class id (0 background .. 20 tvmonitor, see kVocClassNames).

#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace esdslam {

// The 21 PASCAL VOC class names, index = class id.
const std::vector<std::string>& VocClassNames();
inline constexpr int kVocPersonClass = 15;

struct SegmentationResult {
  cv::Mat labels;              // CV_8UC1 class ids at the input image's resolution
  cv::Mat person_probability;  // CV_32FC1 in [0,1] at image resolution, or empty if not computed
  double segment_ms = 0.0;     // wall time spent in Segment()
};

class Segmenter {
 public:
  virtual ~Segmenter() = default;
  // `bgr` is CV_8UC3; `timestamp` in seconds (used by segmenters that look results up by time).
  // Throws esdslam::Error on failure. Not required to be thread-safe: call from one thread.
  virtual SegmentationResult Segment(const cv::Mat& bgr, double timestamp) = 0;
  virtual std::string Name() const = 0;
};

}  // namespace esdslam
