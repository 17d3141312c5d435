#include "map/map.h"

namespace esdslam {

KeyFrame* Map::CreateKeyFrame(long frame_id, double timestamp, std::shared_ptr<const FeatureSet> features,
                              const Rigid3& cam_from_world) {
  auto keyframe = std::make_unique<KeyFrame>(next_keyframe_id_++, frame_id, timestamp, std::move(features),
                                             cam_from_world, this);
  std::lock_guard<std::mutex> lock(mutex_);
  keyframe_storage_.push_back(std::move(keyframe));
  return keyframe_storage_.back().get();
}

MapPoint* Map::CreateMapPoint(const Vec3& position_world, KeyFrame* reference_keyframe) {
  auto point = std::make_unique<MapPoint>(next_point_id_++, position_world, reference_keyframe, this);
  std::lock_guard<std::mutex> lock(mutex_);
  point_storage_.push_back(std::move(point));
  return point_storage_.back().get();
}

void Map::AddKeyFrame(KeyFrame* keyframe) {
  std::lock_guard<std::mutex> lock(mutex_);
  keyframes_.insert(keyframe);
}
void Map::AddMapPoint(MapPoint* point) {
  std::lock_guard<std::mutex> lock(mutex_);
  points_.insert(point);
}
void Map::EraseKeyFrame(KeyFrame* keyframe) {
  std::lock_guard<std::mutex> lock(mutex_);
  keyframes_.erase(keyframe);
}
void Map::EraseMapPoint(MapPoint* point) {
  std::lock_guard<std::mutex> lock(mutex_);
  points_.erase(point);
}

std::vector<KeyFrame*> Map::keyframes() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return {keyframes_.begin(), keyframes_.end()};
}
std::vector<MapPoint*> Map::map_points() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return {points_.begin(), points_.end()};
}
int Map::num_keyframes() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return static_cast<int>(keyframes_.size());
}
int Map::num_map_points() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return static_cast<int>(points_.size());
}

}  // namespace esdslam
