// Tracker's LOST-state hook into global BoW relocalization (see relocalizer.h).
#include <spdlog/spdlog.h>

#include "map/keyframe.h"
#include "tracking/relocalizer.h"
#include "tracking/tracker.h"

namespace esdslam {

// On success the candidate keyframe becomes the reference; the motion model restarts (the last
// frame had no pose) and Track() continues with local-map tracking.
bool Tracker::Relocalize(Frame* frame) {
  RelocalizationStats stats;
  KeyFrame* keyframe = relocalizer_->Relocalize(frame, options_.pose, map_->keyframes(), &stats);
  if (keyframe == nullptr) return false;
  reference_keyframe_ = keyframe;
  if (last_keyframe_ == nullptr) last_keyframe_ = keyframe;  // loaded map: none created yet
  velocity_valid_ = false;
  ++relocalizations_;
  last_relocalization_frame_id_ = frame->id();
  spdlog::info("tracking: relocalized frame {} against keyframe {} ({} inliers)", frame->id(), keyframe->id(),
               stats.inliers);
  return true;
}

}  // namespace esdslam
