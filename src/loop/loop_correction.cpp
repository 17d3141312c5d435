#include "loop/loop_correction.h"

#include "loop/loop_projection.h"
#include "map/keyframe.h"
#include "map/map_point.h"

namespace esdslam {

std::map<long, Rigid3> PropagateCorrection(const Rigid3& current_cam_from_world, const Rigid3& current_corrected,
                                           const std::map<long, Rigid3>& group_cam_from_world) {
  const Rigid3 world_from_current = current_cam_from_world.inverse();
  std::map<long, Rigid3> corrected;
  for (const auto& [id, cam_from_world] : group_cam_from_world)
    corrected[id] = (cam_from_world * world_from_current) * current_corrected;
  return corrected;
}

GroupCorrection CorrectCurrentGroup(KeyFrame* current, const Rigid3& current_corrected) {
  GroupCorrection correction;
  std::set<KeyFrame*, KeyFrameIdLess> members{current};
  for (KeyFrame* keyframe : current->covisible_keyframes())
    if (!keyframe->is_bad()) members.insert(keyframe);
  correction.group.assign(members.begin(), members.end());
  std::map<long, Rigid3> before;
  for (KeyFrame* keyframe : correction.group) {
    before[keyframe->id()] = keyframe->cam_from_world();
    correction.non_corrected[keyframe] = before[keyframe->id()];
  }
  const std::map<long, Rigid3> after = PropagateCorrection(current->cam_from_world(), current_corrected, before);
  for (KeyFrame* keyframe : correction.group) {
    const Rigid3& old_pose = before.at(keyframe->id());
    const Rigid3& new_pose = after.at(keyframe->id());
    correction.corrected[keyframe] = new_pose;
    const Rigid3 new_world_from_old_world = new_pose.inverse() * old_pose;
    for (MapPoint* point : keyframe->valid_map_points()) {
      if (!correction.corrected_by.emplace(point, keyframe).second) continue;
      point->set_position(new_world_from_old_world * point->position());
    }
  }
  for (KeyFrame* keyframe : correction.group) keyframe->set_cam_from_world(correction.corrected.at(keyframe));
  for (const auto& [point, keyframe] : correction.corrected_by) point->UpdateNormalAndDepth();
  return correction;
}

namespace {

// `existing` hands its observations to `loop_point` (followed through earlier replacements).
bool ReplaceByLoopPoint(MapPoint* existing, MapPoint* loop_point) {
  MapPoint* target = loop_point->replaced_by();
  if (target->is_bad() || existing->is_bad() || target == existing) return false;
  existing->Replace(target);
  target->UpdateNormalAndDepth();
  return true;
}

}  // namespace

int FuseLoopMatches(KeyFrame* current, const std::vector<MapPoint*>& matched_points) {
  int fused = 0;
  for (int i = 0; i < static_cast<int>(matched_points.size()); ++i) {
    if (matched_points[i] == nullptr) continue;
    MapPoint* loop_point = matched_points[i]->replaced_by();
    if (loop_point->is_bad()) continue;
    MapPoint* existing = current->map_point(i);
    if (existing == loop_point) continue;
    if (existing != nullptr && !existing->is_bad()) {
      fused += ReplaceByLoopPoint(existing, loop_point) ? 1 : 0;
    } else if (!loop_point->IsObservedBy(current)) {
      current->AddMapPoint(loop_point, i);
      loop_point->AddObservation(current, i, current->features().has_depth(i));
      loop_point->ComputeDistinctiveDescriptor();
      loop_point->UpdateNormalAndDepth();
      ++fused;
    }
  }
  return fused;
}

int FuseLoopPointsIntoGroup(const GroupCorrection& correction, const std::vector<MapPoint*>& loop_points,
                            double radius_factor) {
  int fused = 0;
  for (KeyFrame* keyframe : correction.group) {
    if (keyframe->is_bad()) continue;
    const LoopFuseResult result = FuseLoopPoints(keyframe, loop_points, radius_factor);
    fused += result.observations_added;
    for (const auto& [existing, loop_point] : result.replacements) fused += ReplaceByLoopPoint(existing, loop_point) ? 1 : 0;
  }
  return fused;
}

std::map<KeyFrame*, std::set<KeyFrame*, KeyFrameIdLess>, KeyFrameIdLess> NewLoopConnections(
    const GroupCorrection& correction) {
  std::map<KeyFrame*, std::vector<KeyFrame*>, KeyFrameIdLess> previous;
  for (KeyFrame* keyframe : correction.group) previous[keyframe] = keyframe->covisible_keyframes();
  for (KeyFrame* keyframe : correction.group)
    if (!keyframe->is_bad()) keyframe->UpdateConnections();
  const std::set<KeyFrame*, KeyFrameIdLess> members(correction.group.begin(), correction.group.end());
  std::map<KeyFrame*, std::set<KeyFrame*, KeyFrameIdLess>, KeyFrameIdLess> connections;
  for (KeyFrame* keyframe : correction.group) {
    if (keyframe->is_bad()) continue;
    const std::set<KeyFrame*, KeyFrameIdLess> before(previous[keyframe].begin(), previous[keyframe].end());
    for (const auto& [other, weight] : keyframe->connection_weights()) {
      (void)weight;
      if (!other->is_bad() && !before.count(other) && !members.count(other)) connections[keyframe].insert(other);
    }
  }
  return connections;
}

}  // namespace esdslam
