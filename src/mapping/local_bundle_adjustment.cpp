// Local bundle adjustment over the covisible window (ORB-SLAM2's LocalBundleAdjustment).
#include <map>
#include <unordered_set>

#include "map/keyframe.h"
#include "map/map_point.h"
#include "mapping/mapping_steps.h"

namespace esdslam {
namespace {

struct Window {
  std::vector<KeyFrame*> keyframes;  // local first, then fixed
  std::vector<MapPoint*> points;
  std::vector<std::pair<int, int>> observation_keys;  // (keyframe index, keypoint index) per observation
  BaProblem problem;
};

Window BuildWindow(KeyFrame* keyframe) {
  Window window;
  std::map<KeyFrame*, int, KeyFrameIdLess> index_of;
  const auto add_keyframe = [&](KeyFrame* kf, bool fixed) {
    index_of[kf] = static_cast<int>(window.keyframes.size());
    window.keyframes.push_back(kf);
    window.problem.keyframes.push_back({kf->cam_from_world(), fixed});
  };
  add_keyframe(keyframe, keyframe->id() == 0);
  for (KeyFrame* covisible : keyframe->covisible_keyframes())
    if (!covisible->is_bad() && !index_of.count(covisible)) add_keyframe(covisible, covisible->id() == 0);
  const std::size_t num_local = window.keyframes.size();
  std::unordered_set<const MapPoint*> added;
  for (std::size_t k = 0; k < num_local; ++k)
    for (MapPoint* point : window.keyframes[k]->valid_map_points())
      if (added.insert(point).second) window.points.push_back(point);
  for (MapPoint* point : window.points)
    for (KeyFrame* observer : point->observing_keyframes())
      if (!observer->is_bad() && !index_of.count(observer)) add_keyframe(observer, true);
  for (std::size_t p = 0; p < window.points.size(); ++p) {
    window.problem.points.push_back({window.points[p]->position(), false});
    for (const auto& [observer, index] : window.points[p]->observations()) {
      auto it = index_of.find(observer);
      if (it == index_of.end()) continue;
      const FeatureSet& features = observer->features();
      BaObservation observation;
      observation.keyframe = it->second;
      observation.point = static_cast<int>(p);
      observation.pixel = features.pixel(index);
      observation.right_u = features.right_u[index];
      observation.information = features.rig->pyramid.inv_level_sigma2[features.level(index)];
      window.problem.observations.push_back(observation);
      window.observation_keys.emplace_back(it->second, index);
    }
  }
  return window;
}

void WriteBack(const Window& window) {
  for (std::size_t o = 0; o < window.problem.observations.size(); ++o) {
    const BaObservation& observation = window.problem.observations[o];
    if (!observation.outlier) continue;
    KeyFrame* keyframe = window.keyframes[observation.keyframe];
    MapPoint* point = window.points[observation.point];
    if (point->KeypointIndexIn(keyframe) != window.observation_keys[o].second) continue;
    keyframe->EraseMapPoint(window.observation_keys[o].second);
    point->EraseObservation(keyframe);
  }
  for (std::size_t k = 0; k < window.keyframes.size(); ++k)
    if (!window.problem.keyframes[k].fixed) window.keyframes[k]->set_cam_from_world(window.problem.keyframes[k].cam_from_world);
  for (std::size_t p = 0; p < window.points.size(); ++p) {
    if (window.points[p]->is_bad()) continue;
    window.points[p]->set_position(window.problem.points[p].position_world);
    window.points[p]->UpdateNormalAndDepth();
  }
}

}  // namespace

BaSummary LocalBundleAdjustment(Map* map, KeyFrame* keyframe, const BundleAdjustmentOptions& options,
                                const std::atomic<bool>* stop) {
  Window window;
  {
    std::lock_guard<std::mutex> lock(map->update_mutex());
    if (keyframe->is_bad()) return {};
    window = BuildWindow(keyframe);
  }
  if (window.problem.observations.empty()) return {};
  const RgbdRig& rig = keyframe->rig();
  // Solved without the map lock: only local mapping changes these objects' structure, and it is
  // busy here; tracking only reads them.
  BaSummary summary = BundleAdjust(rig.camera, rig.bf, options, &window.problem, stop);
  std::lock_guard<std::mutex> lock(map->update_mutex());
  WriteBack(window);
  return summary;
}

}  // namespace esdslam
