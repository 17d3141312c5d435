// KeyFrame culling: removal from the covisibility graph and spanning-tree repair.
#include "map/keyframe.h"
#include "map/map.h"
#include "map/map_point.h"

namespace esdslam {

void KeyFrame::SetBad() {
  if (id_ == 0 || is_bad()) return;
  for (const auto& [other, weight] : connection_weights()) {
    (void)weight;
    other->EraseConnection(this);
  }
  const std::vector<MapPoint*> points = map_points();
  for (std::size_t i = 0; i < points.size(); ++i)
    if (points[i] != nullptr) points[i]->EraseObservation(this);
  {
    std::lock_guard<std::mutex> lock(mutex_connections_);
    connection_weights_.clear();
    ordered_connections_.clear();
    ordered_weights_.clear();
  }
  {
    std::lock_guard<std::mutex> lock(mutex_points_);
    std::fill(map_points_.begin(), map_points_.end(), nullptr);
  }
  ReassignChildren();
  KeyFrame* my_parent = parent();
  const Rigid3 relative = my_parent != nullptr ? cam_from_world() * my_parent->world_from_cam() : Rigid3();
  if (my_parent != nullptr) my_parent->EraseChild(this);
  {
    std::lock_guard<std::mutex> lock(mutex_connections_);
    cam_from_parent_ = relative;
    bad_ = true;
  }
  map_->EraseKeyFrame(this);
}

// Each child gets as new parent the candidate (the old parent, or an already re-parented sibling)
// it shares the most points with; children with no covisible candidate go to the old parent.
void KeyFrame::ReassignChildren() {
  KeyFrame* my_parent = parent();
  if (my_parent == nullptr) return;
  std::set<KeyFrame*, KeyFrameIdLess> candidates{my_parent};
  std::set<KeyFrame*, KeyFrameIdLess> remaining = children();
  while (!remaining.empty()) {
    KeyFrame* best_child = nullptr;
    KeyFrame* best_parent = nullptr;
    int best_weight = -1;
    for (KeyFrame* child : remaining) {
      if (child->is_bad()) continue;
      for (KeyFrame* covisible : child->covisible_keyframes()) {
        if (!candidates.count(covisible)) continue;
        const int weight = child->Weight(covisible);
        if (weight > best_weight) best_weight = weight, best_child = child, best_parent = covisible;
      }
    }
    if (best_child == nullptr) break;
    best_child->ChangeParent(best_parent);
    candidates.insert(best_child);
    remaining.erase(best_child);
  }
  for (KeyFrame* child : remaining) child->ChangeParent(my_parent);
  std::lock_guard<std::mutex> lock(mutex_connections_);
  children_.clear();
}

KeyFrame* LiveAncestor(KeyFrame* keyframe, Rigid3* cam_from_keyframe) {
  while (keyframe != nullptr && keyframe->is_bad() && keyframe->parent() != nullptr) {
    *cam_from_keyframe = *cam_from_keyframe * keyframe->cam_from_parent();
    keyframe = keyframe->parent();
  }
  return keyframe;
}

}  // namespace esdslam
