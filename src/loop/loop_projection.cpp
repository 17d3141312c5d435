#include "loop/loop_projection.h"

#include <set>

#include "feature/descriptor.h"
#include "map/keyframe.h"
#include "map/map_point.h"

namespace esdslam {
namespace {

// The keyframe's keypoints found dynamic after it was made (KeyFrame::late_dynamic), as flags
// (all false when none): never matched.
std::vector<bool> LateDynamicKeypoints(const KeyFrame& keyframe) {
  std::vector<bool> flags(static_cast<std::size_t>(keyframe.features().size()), false);
  if (const auto late = keyframe.late_dynamic())
    for (std::size_t i = 0; i < flags.size(); ++i) flags[i] = (*late)[i] != 0;
  return flags;
}

}  // namespace

int ProjectionMatch(const KeyFrame& keyframe, const Rigid3& cam_from_world, const MapPoint& point, double radius_factor,
                    const std::vector<bool>* blocked, int max_distance) {
  const RgbdRig& rig = keyframe.rig();
  const FeatureSet& features = keyframe.features();
  const Vec3 position = point.position();
  const Vec3 p_cam = cam_from_world * position;
  if (p_cam.z() <= 0) return -1;
  const Vec2 pixel = rig.camera.Project(p_cam);
  if (!rig.camera.InImage(pixel)) return -1;
  const Vec3 ray = position - cam_from_world.inverse().translation();
  const double distance = ray.norm();
  if (distance < point.min_distance() || distance > point.max_distance()) return -1;
  if (ray.dot(point.normal()) < 0.5 * distance) return -1;
  const cv::Mat descriptor = point.descriptor();
  if (descriptor.empty()) return -1;
  const int level = point.PredictLevel(distance, rig.pyramid.num_levels, rig.pyramid.log_scale_factor);
  const double radius = radius_factor * rig.pyramid.scale_factors[level];
  int best = -1, best_distance = 256;
  for (int j : keyframe.FeaturesInArea(pixel.x(), pixel.y(), radius)) {
    const int keypoint_level = features.level(j);
    if (keypoint_level < level - 1 || keypoint_level > level || features.is_dynamic[j]) continue;
    if (blocked != nullptr && (*blocked)[j]) continue;
    const int d = DescriptorDistance(descriptor.ptr<unsigned char>(0), features.descriptor(j));
    if (d < best_distance) best_distance = d, best = j;
  }
  return best_distance <= max_distance ? best : -1;
}

int SearchByProjection(const KeyFrame& keyframe, const Rigid3& cam_from_world, const std::vector<MapPoint*>& points,
                       double radius_factor, std::vector<MapPoint*>* matched) {
  const std::set<MapPoint*> already(matched->begin(), matched->end());
  std::vector<bool> blocked = LateDynamicKeypoints(keyframe);
  for (std::size_t i = 0; i < matched->size(); ++i) blocked[i] = blocked[i] || (*matched)[i] != nullptr;
  int added = 0;
  for (MapPoint* point : points) {
    if (point == nullptr || point->is_bad() || already.count(point)) continue;
    const int index = ProjectionMatch(keyframe, cam_from_world, *point, radius_factor, &blocked, kDescriptorDistanceLow);
    if (index < 0) continue;
    (*matched)[index] = point;
    blocked[index] = true;
    ++added;
  }
  return added;
}

LoopFuseResult FuseLoopPoints(KeyFrame* keyframe, const std::vector<MapPoint*>& loop_points, double radius_factor) {
  LoopFuseResult result;
  const Rigid3 cam_from_world = keyframe->cam_from_world();
  std::set<MapPoint*> replaced;  // each keyframe point is taken over at most once
  const std::vector<bool> late_dynamic = LateDynamicKeypoints(*keyframe);
  for (MapPoint* point : loop_points) {
    if (point == nullptr || point->is_bad() || point->IsObservedBy(keyframe)) continue;
    const int index = ProjectionMatch(*keyframe, cam_from_world, *point, radius_factor, &late_dynamic, kDescriptorDistanceLow);
    if (index < 0) continue;
    MapPoint* existing = keyframe->map_point(index);
    if (existing != nullptr && !existing->is_bad()) {
      if (existing != point && replaced.insert(existing).second) result.replacements.emplace_back(existing, point);
    } else {
      point->AddObservation(keyframe, index, keyframe->features().has_depth(index));
      keyframe->AddMapPoint(point, index);
      ++result.observations_added;
    }
  }
  return result;
}

}  // namespace esdslam
