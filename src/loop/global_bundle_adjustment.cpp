#include "loop/global_bundle_adjustment.h"

#include <deque>
#include <set>

#include "common/error.h"
#include "map/keyframe.h"
#include "map/map_point.h"

namespace esdslam {

void GlobalBundleAdjustmentOptions::Check() const {
  if (iterations < 1) throw Error("global BA: iterations must be >= 1");
}

namespace {

void AddObservations(const std::map<const KeyFrame*, int>& index_of, int point_index, const MapPoint& point,
                     BaProblem* problem) {
  for (const auto& [observer, keypoint] : point.observations()) {
    const auto it = index_of.find(observer);
    if (it == index_of.end()) continue;
    const FeatureSet& features = observer->features();
    BaObservation observation;
    observation.keyframe = it->second;
    observation.point = point_index;
    observation.pixel = features.pixel(keypoint);
    observation.right_u = features.right_u[keypoint];
    observation.information = features.rig->pyramid.inv_level_sigma2[features.level(keypoint)];
    problem->observations.push_back(observation);
  }
}

}  // namespace

GlobalBaSnapshot BuildGlobalBundleAdjustment(const Map& map) {
  GlobalBaSnapshot snapshot;
  std::map<const KeyFrame*, int> index_of;
  for (KeyFrame* keyframe : map.keyframes()) {
    if (keyframe->is_bad()) continue;
    index_of[keyframe] = static_cast<int>(snapshot.keyframes.size());
    // The first keyframe (lowest id, never culled) fixes the gauge.
    snapshot.problem.keyframes.push_back({keyframe->cam_from_world(), snapshot.keyframes.empty()});
    snapshot.keyframes.push_back(keyframe);
  }
  for (MapPoint* point : map.map_points()) {
    if (point->is_bad()) continue;
    const std::size_t before = snapshot.problem.observations.size();
    AddObservations(index_of, static_cast<int>(snapshot.points.size()), *point, &snapshot.problem);
    if (snapshot.problem.observations.size() == before) continue;
    snapshot.problem.points.push_back({point->position(), false});
    snapshot.points.push_back(point);
  }
  return snapshot;
}

BaSummary SolveGlobalBundleAdjustment(const GlobalBundleAdjustmentOptions& options, GlobalBaSnapshot* snapshot,
                                      const std::atomic<bool>* stop) {
  options.Check();
  if (snapshot->keyframes.size() < 2 || snapshot->problem.observations.empty()) return {};
  BundleAdjustmentOptions ba;
  ba.iterations_first = options.iterations;
  ba.iterations_second = 0;  // robust loss throughout; outliers stay in the map (as ORB-SLAM2)
  const RgbdRig& rig = snapshot->keyframes.front()->rig();
  return BundleAdjust(rig.camera, rig.bf, ba, &snapshot->problem, stop);
}

std::map<long, Rigid3> PropagateThroughSpanningTree(const std::map<long, Rigid3>& cam_from_world,
                                                    const std::map<long, long>& parent_of,
                                                    const std::map<long, Rigid3>& optimized) {
  std::map<long, std::vector<long>> children;
  std::deque<long> pending;
  for (const auto& [id, pose] : cam_from_world) {
    const auto parent = parent_of.find(id);
    if (parent != parent_of.end() && parent->second != id && cam_from_world.count(parent->second))
      children[parent->second].push_back(id);
    else
      pending.push_back(id);  // a root
  }
  std::map<long, Rigid3> result = cam_from_world;
  std::set<long> done;
  for (const long root : pending) {
    const auto solved = optimized.find(root);
    if (solved != optimized.end()) result[root] = solved->second;
    done.insert(root);
  }
  while (!pending.empty()) {
    const long node = pending.front();
    pending.pop_front();
    for (const long child : children[node]) {
      if (!done.insert(child).second) continue;
      const auto solved = optimized.find(child);
      result[child] = solved != optimized.end()
                          ? solved->second
                          : (cam_from_world.at(child) * cam_from_world.at(node).inverse()) * result.at(node);
      pending.push_back(child);
    }
  }
  return result;
}

GlobalBaMergeSummary MergeGlobalBundleAdjustment(Map* map, const GlobalBaSnapshot& solved) {
  GlobalBaMergeSummary summary;
  std::map<long, Rigid3> before, optimized;
  std::map<long, long> parent_of;
  const std::vector<KeyFrame*> keyframes = map->keyframes();
  for (KeyFrame* keyframe : keyframes) {
    before[keyframe->id()] = keyframe->cam_from_world();
    KeyFrame* parent = keyframe->parent();
    if (parent != nullptr) parent_of[keyframe->id()] = parent->id();
  }
  for (std::size_t i = 0; i < solved.keyframes.size(); ++i)
    if (!solved.keyframes[i]->is_bad()) optimized[solved.keyframes[i]->id()] = solved.problem.keyframes[i].cam_from_world;
  const std::map<long, Rigid3> after = PropagateThroughSpanningTree(before, parent_of, optimized);
  for (KeyFrame* keyframe : keyframes) {
    keyframe->set_cam_from_world(after.at(keyframe->id()));
    (optimized.count(keyframe->id()) ? summary.keyframes_solved : summary.keyframes_propagated) += 1;
  }
  std::set<MapPoint*, MapPointIdLess> solved_points;
  for (std::size_t i = 0; i < solved.points.size(); ++i) {
    MapPoint* point = solved.points[i];
    if (point->is_bad()) continue;
    point->set_position(solved.problem.points[i].position_world);
    solved_points.insert(point);
    ++summary.points_solved;
  }
  for (MapPoint* point : map->map_points()) {
    KeyFrame* reference = point->reference_keyframe();
    if (point->is_bad() || reference == nullptr || solved_points.count(point) || !before.count(reference->id())) continue;
    point->set_position(after.at(reference->id()).inverse() * (before.at(reference->id()) * point->position()));
    ++summary.points_propagated;
  }
  for (MapPoint* point : map->map_points()) point->UpdateNormalAndDepth();
  return summary;
}

}  // namespace esdslam
