#pragma once
// The tracker's hook for a check that finds keypoints on moving objects once the frame has a
// first pose (implemented by the multi-view geometry check, dynamic/geometry_filter.h). Tracking
// itself knows nothing about dynamic objects beyond FeatureSet::is_dynamic; this interface keeps
// the dependency pointing from dynamic/ to tracking/, not back.
//
// Threading: both calls come from the tracking thread while it holds Map::update_mutex.

namespace esdslam {

class Frame;
class KeyFrame;

class MovingKeypointFilter {
 public:
  virtual ~MovingKeypointFilter() = default;
  // frame: tracked with a first pose and map point associations. Marks the keypoints found
  // moving dynamic (Frame::MarkDynamic, which drops their associations) and returns the number
  // of associations removed; the tracker then re-estimates the pose without them.
  virtual int Apply(Frame* frame) = 0;
  // A keyframe was just made from `frame` (its features are now shared and immutable).
  virtual void AddKeyFrame(const KeyFrame& keyframe, const Frame& frame) = 0;
};

}  // namespace esdslam
