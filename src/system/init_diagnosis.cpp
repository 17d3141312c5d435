#include "system/init_diagnosis.h"

#include <algorithm>

#include <fmt/format.h>

namespace esdslam {

void InitDiagnosis::Add(const FrameReport& report) {
  ++frames_;
  initialised_ = initialised_ || report.track.has_pose;
  if (report.features == nullptr) return;
  const FeatureSet& features = *report.features;
  int with_depth = 0, usable = 0;
  for (int i = 0; i < features.size(); ++i) {
    if (!features.has_depth(i)) continue;
    ++with_depth;
    usable += features.is_dynamic[i] == 0;
  }
  max_keypoints_ = std::max(max_keypoints_, features.size());
  max_with_depth_ = std::max(max_with_depth_, with_depth);
  max_usable_ = std::max(max_usable_, usable);
}

std::string InitDiagnosis::Reason(int needed) const {
  if (initialised_) return "";
  if (frames_ == 0) return "the map never initialised: no frame was tracked";
  if (max_keypoints_ == 0)
    return fmt::format("the map never initialised: no keypoints were found in any of the {} frames (blank or flat images?)",
                       frames_);
  if (max_with_depth_ == 0)
    return fmt::format("the map never initialised: no valid depth; not one keypoint had a depth reading in any of the {} "
                       "frames (depth images all zero, or DepthMapFactor wrong?)",
                       frames_);
  return fmt::format("the map never initialised: too few keypoints; at most {} keypoints of a frame had a valid depth "
                     "and were not dynamic (at most {} had a depth, {} were found), more than {} are needed",
                     max_usable_, max_with_depth_, max_keypoints_, needed);
}

}  // namespace esdslam
