#pragma once
// A 3-D landmark: world position, the keyframes that observe it (keyframe -> keypoint index),
// a representative descriptor, mean viewing direction and the distance range over which ORB can
// detect it (scale invariance). Owned by Map; never freed before the Map, so raw pointers held by
// frames stay valid (a culled point is only flagged bad).
//
// Locking: position/normal/distances under mutex_position_; observations, descriptor, reference
// keyframe, bad/replaced flags under mutex_observations_. A method locks only this point's own
// mutexes and never calls into another object while holding them (see docs/CORE.md).

#include <atomic>
#include <map>
#include <mutex>
#include <vector>

#include <opencv2/core.hpp>

#include "common/geometry.h"
#include "map/map_types.h"

namespace esdslam {

class MapPoint {
 public:
  MapPoint(long id, const Vec3& position_world, KeyFrame* reference_keyframe, Map* map);

  long id() const { return id_; }
  long first_keyframe_id() const { return first_keyframe_id_; }

  Vec3 position() const;
  void set_position(const Vec3& position_world);
  Vec3 normal() const;  // unit mean viewing direction (from cameras to the point), world frame
  double min_distance() const;  // 0.8 * scale-invariance lower bound (m)
  double max_distance() const;  // 1.2 * scale-invariance upper bound (m)
  // Pyramid level at which the point should appear when seen from `distance` metres.
  int PredictLevel(double distance, int num_levels, double log_scale_factor) const;

  // Observations.
  std::map<KeyFrame*, int, KeyFrameIdLess> observations() const;
  // The observing keyframes alone, in the same (id) order: one allocation instead of a tree copy,
  // for the hot loops that only count keyframes (tracking's local map, the geometry check's
  // references, covisibility, local BA).
  std::vector<KeyFrame*> observing_keyframes() const;
  void AddObservation(KeyFrame* keyframe, int keypoint_index, bool with_depth);
  // Removes the observation; flags the point bad when fewer than 2 weighted observations remain.
  void EraseObservation(KeyFrame* keyframe);
  int KeypointIndexIn(const KeyFrame* keyframe) const;  // -1 when not observed there
  bool IsObservedBy(const KeyFrame* keyframe) const { return KeypointIndexIn(keyframe) >= 0; }
  // ORB-SLAM2's count: 2 for an observation with depth, 1 without.
  int num_observations() const;
  int num_observing_keyframes() const;
  KeyFrame* reference_keyframe() const;

  cv::Mat descriptor() const;  // 1 x 32 CV_8U copy
  void set_descriptor(const cv::Mat& descriptor);  // 1 x 32 CV_8U (copied)
  // Picks the observed descriptor with the least median Hamming distance to the others.
  void ComputeDistinctiveDescriptor();
  // Recomputes the mean viewing direction and the scale-invariance distances.
  void UpdateNormalAndDepth();

  // Removes the point from every observing keyframe and from the map.
  void SetBad();
  bool is_bad() const;
  // Moves all observations to `other` (which takes over this point) and flags this one bad.
  void Replace(MapPoint* other);
  // Follows replaced-by links; returns this point when never replaced.
  MapPoint* replaced_by() const;

  // Tracking statistics: frames in whose frustum the point was / in which it was matched.
  void IncreaseVisible(int n = 1) { visible_ += n; }
  void IncreaseFound(int n = 1) { found_ += n; }
  double found_ratio() const { return static_cast<double>(found_) / std::max(1, visible_.load()); }

 private:
  const long id_;
  const long first_keyframe_id_;
  Map* const map_;

  mutable std::mutex mutex_position_;
  Vec3 position_;
  Vec3 normal_ = Vec3::Zero();
  double min_distance_ = 0, max_distance_ = 0;

  mutable std::mutex mutex_observations_;
  std::map<KeyFrame*, int, KeyFrameIdLess> observations_;
  int num_observations_ = 0;
  cv::Mat descriptor_;
  KeyFrame* reference_keyframe_;
  bool bad_ = false;
  MapPoint* replaced_by_ = nullptr;

  std::atomic<int> visible_{1};
  std::atomic<int> found_{1};
};

}  // namespace esdslam
