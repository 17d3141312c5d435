#pragma once
// The map: owns every KeyFrame and MapPoint ever created (objects are freed only with the Map, so
// raw pointers stay valid after culling) and keeps the sets of live ones.
//
// `update_mutex()` is the map-structure lock (ORB-SLAM2's mMutexMapUpdate): the tracking thread
// holds it for a whole tracking step (it reads the local map), the local-mapping thread holds it
// while it changes the map structure and while it writes back bundle adjustment results.
// See docs/CORE.md for the complete lock order.

#include <atomic>
#include <memory>
#include <mutex>
#include <set>
#include <vector>

#include "map/keyframe.h"
#include "map/map_point.h"

namespace esdslam {

class Map {
 public:
  Map() = default;
  Map(const Map&) = delete;
  Map& operator=(const Map&) = delete;

  // Factories: create an object owned by the map (not yet "in" the map until Add*).
  KeyFrame* CreateKeyFrame(long frame_id, double timestamp, std::shared_ptr<const FeatureSet> features,
                           const Rigid3& cam_from_world);
  MapPoint* CreateMapPoint(const Vec3& position_world, KeyFrame* reference_keyframe);

  void AddKeyFrame(KeyFrame* keyframe);
  void AddMapPoint(MapPoint* point);
  void EraseKeyFrame(KeyFrame* keyframe);
  void EraseMapPoint(MapPoint* point);

  std::vector<KeyFrame*> keyframes() const;  // live, id order
  std::vector<MapPoint*> map_points() const;  // live, id order
  int num_keyframes() const;
  int num_map_points() const;
  long max_keyframe_id() const { return next_keyframe_id_ - 1; }

  std::mutex& update_mutex() { return update_mutex_; }

 private:
  std::mutex update_mutex_;
  mutable std::mutex mutex_;
  std::vector<std::unique_ptr<KeyFrame>> keyframe_storage_;
  std::vector<std::unique_ptr<MapPoint>> point_storage_;
  std::set<KeyFrame*, KeyFrameIdLess> keyframes_;
  std::set<MapPoint*, MapPointIdLess> points_;
  std::atomic<long> next_keyframe_id_{0};
  std::atomic<long> next_point_id_{0};
};

}  // namespace esdslam
