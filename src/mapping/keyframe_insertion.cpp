#include <algorithm>

#include "map/keyframe.h"
#include "map/map_point.h"
#include "mapping/mapping_steps.h"

namespace esdslam {

void InsertKeyFrameIntoMap(Map* map, KeyFrame* keyframe, std::vector<MapPoint*>* recent_points) {
  const std::vector<MapPoint*> points = keyframe->map_points();
  for (int i = 0; i < static_cast<int>(points.size()); ++i) {
    MapPoint* point = points[i];
    if (point == nullptr) continue;
    if (point->is_bad()) {
      keyframe->EraseMapPoint(i);
      continue;
    }
    const int existing = point->KeypointIndexIn(keyframe);
    if (existing < 0) {
      point->AddObservation(keyframe, i, keyframe->features().has_depth(i));
      point->UpdateNormalAndDepth();
      point->ComputeDistinctiveDescriptor();
    } else if (existing == i) {
      recent_points->push_back(point);  // created by tracking for this keyframe
    } else {
      keyframe->EraseMapPoint(i);  // a point matched twice in one keyframe keeps its first index
    }
  }
  keyframe->UpdateConnections();
  map->AddKeyFrame(keyframe);
}

int CullRecentMapPoints(const KeyFrame& current, const RecentPointCulling& options,
                        std::vector<MapPoint*>* recent_points) {
  int culled = 0;
  std::vector<MapPoint*> kept;
  for (MapPoint* point : *recent_points) {
    if (point->is_bad()) continue;
    const long age = current.id() - point->first_keyframe_id();
    if (point->found_ratio() < options.min_found_ratio ||
        (age >= options.keyframes_before_check && point->num_observations() <= options.min_observations)) {
      point->SetBad();
      ++culled;
    } else if (age < options.keyframes_until_kept) {
      kept.push_back(point);
    }
  }
  recent_points->swap(kept);
  return culled;
}

int CullRedundantKeyFrames(Map* map, KeyFrame* keyframe, const RedundantKeyFrameCulling& options) {
  (void)map;
  int culled = 0;
  for (KeyFrame* candidate : keyframe->covisible_keyframes()) {
    if (candidate->id() == 0 || candidate->is_bad()) continue;
    const FeatureSet& features = candidate->features();
    const std::vector<MapPoint*> points = candidate->map_points();
    int close_points = 0, redundant = 0;
    for (int i = 0; i < static_cast<int>(points.size()); ++i) {
      MapPoint* point = points[i];
      if (point == nullptr || point->is_bad() || !features.is_close(i)) continue;
      ++close_points;
      if (point->num_observations() <= options.min_other_observers) continue;
      const int level = features.level(i);
      int observers = 0;
      for (const auto& [other, index] : point->observations()) {
        if (other == candidate) continue;
        if (other->features().level(index) <= level + 1 && ++observers >= options.min_other_observers) break;
      }
      if (observers >= options.min_other_observers) ++redundant;
    }
    if (close_points > 0 && redundant > options.redundant_ratio * close_points) {
      candidate->SetBad();
      ++culled;
    }
  }
  return culled;
}

}  // namespace esdslam
