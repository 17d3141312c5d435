#pragma once
// Why a run's map never initialised, told from its frames' reports: the map starts at the first
// frame with more than TrackerOptions::min_initial_depth_keypoints keypoints that have a valid
// depth and are not dynamic. A run where no frame got there ends with 0 poses; the reason given
// is the first of: no frame read, no keypoints at all (blank images), no keypoint with a valid
// depth in any frame (depth images all zero, or DepthMapFactor wrong), too few usable keypoints.

#include <string>

#include "system/frame_report.h"

namespace esdslam {

class InitDiagnosis {
 public:
  void Add(const FrameReport& report);  // one tracked frame
  bool initialised() const { return initialised_; }
  // Empty once a frame got a pose; else one sentence saying why no frame did.
  // needed: min_initial_depth_keypoints (more than this many are needed).
  std::string Reason(int needed) const;

 private:
  bool initialised_ = false;
  int frames_ = 0;
  int max_keypoints_ = 0;   // most keypoints extracted in one frame
  int max_with_depth_ = 0;  // most keypoints with a valid depth in one frame
  int max_usable_ = 0;      // most keypoints with a valid depth and not dynamic in one frame
};

}  // namespace esdslam
