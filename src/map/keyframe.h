#pragma once
// A keyframe: a frame kept in the map with its features, pose, map point associations, its place
// in the covisibility graph (weight = number of map points both keyframes observe) and in the
// spanning tree (parent = the keyframe it shared most points with when it was connected).
// Owned by Map; never freed before the Map (a culled keyframe is only flagged bad).
//
// Locking: pose under mutex_pose_, map point associations under mutex_points_, graph (connections,
// parent, children, bad) under mutex_connections_. A method never holds two of them at once and
// never calls into another object while holding one (see docs/CORE.md).

#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <vector>

#include "common/geometry.h"
#include "map/feature_set.h"
#include "map/map_types.h"

namespace esdslam {

class KeyFrame {
 public:
  // `map_points` are the frame's associations (nullptr = none), indexed like features->keypoints.
  KeyFrame(long id, long frame_id, double timestamp, std::shared_ptr<const FeatureSet> features,
           const Rigid3& cam_from_world, Map* map);

  long id() const { return id_; }
  long frame_id() const { return frame_id_; }
  double timestamp() const { return timestamp_; }
  const FeatureSet& features() const { return *features_; }
  const std::shared_ptr<const FeatureSet>& shared_features() const { return features_; }
  const RgbdRig& rig() const { return *features_->rig; }

  // Pose.
  Rigid3 cam_from_world() const;
  Rigid3 world_from_cam() const;
  Vec3 camera_center() const;  // world frame
  void set_cam_from_world(const Rigid3& cam_from_world);

  // Map point associations (index = keypoint index).
  void AddMapPoint(MapPoint* point, int keypoint_index);
  void EraseMapPoint(int keypoint_index);
  void EraseMapPoint(const MapPoint* point);
  void ReplaceMapPoint(int keypoint_index, MapPoint* point);
  MapPoint* map_point(int keypoint_index) const;
  std::vector<MapPoint*> map_points() const;  // includes nullptr and bad entries
  std::vector<MapPoint*> valid_map_points() const;  // non-null, not bad, in index order
  // Keypoints found dynamic only after the keyframe was made (a dynamic mask that came late:
  // system/pipeline.h): like FeatureSet::is_dynamic, never given a map point again. The flags
  // are replaced as a whole (copy on write), so a reader keeps a consistent set; null when none.
  void MarkLateDynamic(const std::vector<int>& keypoint_indices);
  std::shared_ptr<const std::vector<std::uint8_t>> late_dynamic() const;
  // Points observed by at least `min_observations` (ORB-SLAM2 weighted count; 0 = any).
  int TrackedMapPoints(int min_observations) const;

  // Covisibility graph.
  // Recomputes this keyframe's connections from its map points' observations and adds the
  // reverse edges; sets the spanning-tree parent on the first call (except for the first keyframe).
  void UpdateConnections(int min_weight = 15);
  void AddConnection(KeyFrame* other, int weight);
  void EraseConnection(KeyFrame* other);
  int Weight(KeyFrame* other) const;  // 0 when not connected
  std::map<KeyFrame*, int, KeyFrameIdLess> connection_weights() const;
  std::vector<KeyFrame*> covisible_keyframes() const;  // ordered by decreasing weight
  std::vector<KeyFrame*> BestCovisibleKeyframes(int count) const;
  std::vector<KeyFrame*> CovisibleKeyframesWithWeight(int min_weight) const;

  // Spanning tree.
  KeyFrame* parent() const;
  std::set<KeyFrame*, KeyFrameIdLess> children() const;
  void AddChild(KeyFrame* child);
  void EraseChild(KeyFrame* child);
  void ChangeParent(KeyFrame* parent);
  // For a bad keyframe: its pose relative to its parent at culling time (trajectory output).
  Rigid3 cam_from_parent() const;

  // Culls the keyframe: removes it from the graph and its points' observations, hands its
  // children to new parents (the covisible candidate with the highest weight) and flags it bad.
  // The first keyframe is never culled.
  void SetBad();
  bool is_bad() const;

  // Keypoints within a square window (radius px) around an undistorted pixel.
  std::vector<int> FeaturesInArea(double u, double v, double radius, int min_level = -1,
                                  int max_level = -1) const {
    return features_->grid->FeaturesInArea(u, v, radius, min_level, max_level);
  }
  // Median depth of the keyframe's map points in its camera frame (m).
  double SceneMedianDepth() const;

 private:
  void UpdateOrderedConnections();  // requires mutex_connections_
  void ReassignChildren();

  const long id_;
  const long frame_id_;
  const double timestamp_;
  const std::shared_ptr<const FeatureSet> features_;
  Map* const map_;

  mutable std::mutex mutex_pose_;
  Rigid3 cam_from_world_;
  Rigid3 world_from_cam_;

  mutable std::mutex mutex_points_;
  std::vector<MapPoint*> map_points_;
  std::shared_ptr<const std::vector<std::uint8_t>> late_dynamic_;  // null, or one flag per keypoint

  mutable std::mutex mutex_connections_;
  std::map<KeyFrame*, int, KeyFrameIdLess> connection_weights_;
  std::vector<KeyFrame*> ordered_connections_;
  std::vector<int> ordered_weights_;
  bool first_connection_ = true;
  KeyFrame* parent_ = nullptr;
  std::set<KeyFrame*, KeyFrameIdLess> children_;
  Rigid3 cam_from_parent_;
  bool bad_ = false;
};

// Keypoint i of a keyframe is dynamic: flagged at extraction (features.is_dynamic) or later
// (`late`, KeyFrame::late_dynamic(); may be null).
inline bool IsDynamicKeypoint(const FeatureSet& features, const std::vector<std::uint8_t>* late, int i) {
  return features.is_dynamic[i] != 0 || (late != nullptr && (*late)[i] != 0);
}

// Follows the spanning tree from a (possibly culled) keyframe up to the first live one, composing
// `cam_from_keyframe` (a pose relative to `keyframe`) with each culled keyframe's cam_from_parent.
// Returns the live keyframe (nullptr only for a null input); *cam_from_keyframe is then relative
// to it.
KeyFrame* LiveAncestor(KeyFrame* keyframe, Rigid3* cam_from_keyframe);

}  // namespace esdslam
