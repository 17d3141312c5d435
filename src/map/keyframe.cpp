#include "map/keyframe.h"

#include <algorithm>

#include "map/map.h"
#include "map/map_point.h"

namespace esdslam {

KeyFrame::KeyFrame(long id, long frame_id, double timestamp, std::shared_ptr<const FeatureSet> features,
                   const Rigid3& cam_from_world, Map* map)
    : id_(id),
      frame_id_(frame_id),
      timestamp_(timestamp),
      features_(std::move(features)),
      map_(map),
      cam_from_world_(cam_from_world),
      world_from_cam_(cam_from_world.inverse()),
      map_points_(features_->size(), nullptr) {}

Rigid3 KeyFrame::cam_from_world() const {
  std::lock_guard<std::mutex> lock(mutex_pose_);
  return cam_from_world_;
}
Rigid3 KeyFrame::world_from_cam() const {
  std::lock_guard<std::mutex> lock(mutex_pose_);
  return world_from_cam_;
}
Vec3 KeyFrame::camera_center() const {
  std::lock_guard<std::mutex> lock(mutex_pose_);
  return world_from_cam_.translation();
}
void KeyFrame::set_cam_from_world(const Rigid3& cam_from_world) {
  std::lock_guard<std::mutex> lock(mutex_pose_);
  cam_from_world_ = cam_from_world;
  world_from_cam_ = cam_from_world.inverse();
}

void KeyFrame::AddMapPoint(MapPoint* point, int keypoint_index) {
  std::lock_guard<std::mutex> lock(mutex_points_);
  map_points_[keypoint_index] = point;
}
void KeyFrame::EraseMapPoint(int keypoint_index) {
  std::lock_guard<std::mutex> lock(mutex_points_);
  map_points_[keypoint_index] = nullptr;
}
void KeyFrame::EraseMapPoint(const MapPoint* point) {
  const int index = point->KeypointIndexIn(this);
  if (index >= 0) EraseMapPoint(index);
}
void KeyFrame::ReplaceMapPoint(int keypoint_index, MapPoint* point) { AddMapPoint(point, keypoint_index); }

void KeyFrame::MarkLateDynamic(const std::vector<int>& keypoint_indices) {
  std::lock_guard<std::mutex> lock(mutex_points_);
  auto flags = late_dynamic_ ? std::make_shared<std::vector<std::uint8_t>>(*late_dynamic_)
                             : std::make_shared<std::vector<std::uint8_t>>(map_points_.size(), 0);
  for (const int i : keypoint_indices) flags->at(static_cast<std::size_t>(i)) = 1;
  late_dynamic_ = std::move(flags);
}

std::shared_ptr<const std::vector<std::uint8_t>> KeyFrame::late_dynamic() const {
  std::lock_guard<std::mutex> lock(mutex_points_);
  return late_dynamic_;
}

MapPoint* KeyFrame::map_point(int keypoint_index) const {
  std::lock_guard<std::mutex> lock(mutex_points_);
  return map_points_[keypoint_index];
}
std::vector<MapPoint*> KeyFrame::map_points() const {
  std::lock_guard<std::mutex> lock(mutex_points_);
  return map_points_;
}
std::vector<MapPoint*> KeyFrame::valid_map_points() const {
  std::vector<MapPoint*> out;
  for (MapPoint* point : map_points())
    if (point != nullptr && !point->is_bad()) out.push_back(point);
  return out;
}
int KeyFrame::TrackedMapPoints(int min_observations) const {
  int count = 0;
  for (MapPoint* point : valid_map_points())
    if (min_observations <= 0 || point->num_observations() >= min_observations) ++count;
  return count;
}

void KeyFrame::UpdateConnections(int min_weight) {
  std::map<KeyFrame*, int, KeyFrameIdLess> counts;
  for (MapPoint* point : valid_map_points())
    for (KeyFrame* other : point->observing_keyframes())
      if (other != this && !other->is_bad()) ++counts[other];
  if (counts.empty()) return;
  KeyFrame* best = nullptr;
  int best_weight = 0;
  for (const auto& [other, weight] : counts)
    if (weight > best_weight) best = other, best_weight = weight;
  for (const auto& [other, weight] : counts)
    if (weight >= min_weight || other == best) other->AddConnection(this, weight);

  KeyFrame* new_parent = nullptr;
  {
    std::lock_guard<std::mutex> lock(mutex_connections_);
    connection_weights_ = counts;
    UpdateOrderedConnections();
    if (first_connection_ && id_ != 0 && !ordered_connections_.empty()) {
      new_parent = ordered_connections_.front();
      parent_ = new_parent;
      first_connection_ = false;
    }
  }
  if (new_parent != nullptr) new_parent->AddChild(this);
}

void KeyFrame::UpdateOrderedConnections() {
  // Edges of the ordered list: weight >= 15, or the single best one when none reaches 15.
  std::vector<std::pair<int, KeyFrame*>> edges;
  for (const auto& [other, weight] : connection_weights_) edges.emplace_back(weight, other);
  std::stable_sort(edges.begin(), edges.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  ordered_connections_.clear();
  ordered_weights_.clear();
  for (const auto& [weight, other] : edges) {
    if (weight < 15 && !ordered_connections_.empty()) break;
    ordered_connections_.push_back(other);
    ordered_weights_.push_back(weight);
  }
}

void KeyFrame::AddConnection(KeyFrame* other, int weight) {
  std::lock_guard<std::mutex> lock(mutex_connections_);
  auto it = connection_weights_.find(other);
  if (it != connection_weights_.end() && it->second == weight) return;
  connection_weights_[other] = weight;
  UpdateOrderedConnections();
}
void KeyFrame::EraseConnection(KeyFrame* other) {
  std::lock_guard<std::mutex> lock(mutex_connections_);
  if (connection_weights_.erase(other) > 0) UpdateOrderedConnections();
}
int KeyFrame::Weight(KeyFrame* other) const {
  std::lock_guard<std::mutex> lock(mutex_connections_);
  auto it = connection_weights_.find(other);
  return it == connection_weights_.end() ? 0 : it->second;
}
std::map<KeyFrame*, int, KeyFrameIdLess> KeyFrame::connection_weights() const {
  std::lock_guard<std::mutex> lock(mutex_connections_);
  return connection_weights_;
}
std::vector<KeyFrame*> KeyFrame::covisible_keyframes() const {
  std::lock_guard<std::mutex> lock(mutex_connections_);
  return ordered_connections_;
}
std::vector<KeyFrame*> KeyFrame::BestCovisibleKeyframes(int count) const {
  std::lock_guard<std::mutex> lock(mutex_connections_);
  const auto n = std::min<std::size_t>(ordered_connections_.size(), std::max(count, 0));
  return {ordered_connections_.begin(), ordered_connections_.begin() + n};
}
std::vector<KeyFrame*> KeyFrame::CovisibleKeyframesWithWeight(int min_weight) const {
  std::lock_guard<std::mutex> lock(mutex_connections_);
  std::vector<KeyFrame*> out;
  for (std::size_t i = 0; i < ordered_connections_.size() && ordered_weights_[i] >= min_weight; ++i)
    out.push_back(ordered_connections_[i]);
  return out;
}

KeyFrame* KeyFrame::parent() const {
  std::lock_guard<std::mutex> lock(mutex_connections_);
  return parent_;
}
std::set<KeyFrame*, KeyFrameIdLess> KeyFrame::children() const {
  std::lock_guard<std::mutex> lock(mutex_connections_);
  return children_;
}
void KeyFrame::AddChild(KeyFrame* child) {
  std::lock_guard<std::mutex> lock(mutex_connections_);
  children_.insert(child);
}
void KeyFrame::EraseChild(KeyFrame* child) {
  std::lock_guard<std::mutex> lock(mutex_connections_);
  children_.erase(child);
}
void KeyFrame::ChangeParent(KeyFrame* parent) {
  {
    std::lock_guard<std::mutex> lock(mutex_connections_);
    parent_ = parent;
    first_connection_ = false;
  }
  parent->AddChild(this);
}
Rigid3 KeyFrame::cam_from_parent() const {
  std::lock_guard<std::mutex> lock(mutex_connections_);
  return cam_from_parent_;
}
bool KeyFrame::is_bad() const {
  std::lock_guard<std::mutex> lock(mutex_connections_);
  return bad_;
}

double KeyFrame::SceneMedianDepth() const {
  const Rigid3 pose = cam_from_world();
  std::vector<double> depths;
  for (MapPoint* point : valid_map_points()) depths.push_back((pose * point->position()).z());
  if (depths.empty()) return 0;
  std::nth_element(depths.begin(), depths.begin() + depths.size() / 2, depths.end());
  return depths[depths.size() / 2];
}

}  // namespace esdslam
