#pragma once
// The tracker's hook for a check that finds keypoints on moving objects once the frame has a
// first pose (implemented by the multi-view geometry check, dynamic/geometry_filter.h). Tracking
// itself knows nothing about dynamic objects beyond FeatureSet::is_dynamic; this interface keeps
// the dependency pointing from dynamic/ to tracking/, not back.
//
// The filter is handed to each Tracker::Track call (no state on the tracker), so an
// implementation can keep what it found on that frame and give it to the caller as a value
// (dynamic/geometry_filter.h: GeometryFilterHook).
// Threading: both calls come from the tracking thread while it holds Map::update_mutex.

#include <vector>

namespace esdslam {

class Frame;
class KeyFrame;

// What the check found on one frame. The tracker applies it: the keypoints become dynamic
// (Frame::MarkDynamic drops their associations), associations to culled points are dropped, and
// when associations were removed the pose is estimated again without them.
struct MovingKeypoints {
  std::vector<int> keypoints;    // keypoint indices found moving (not yet dynamic), ascending
  int associations_removed = 0;  // of those, keypoints associated with a map point
  int points_culled = 0;         // map points the check set bad (MapPoint::SetBad)
};

class MovingKeypointFilter {
 public:
  virtual ~MovingKeypointFilter() = default;
  // frame: tracked with a first pose and map point associations; it is not changed (the map's
  // points may be: moved points are culled).
  virtual MovingKeypoints FindMoving(const Frame& frame) = 0;
  // A keyframe was just made from `frame` (its features are now shared and immutable).
  virtual void AddKeyFrame(const KeyFrame& keyframe, const Frame& frame) = 0;
};

}  // namespace esdslam
