// Duplicate fusion between a keyframe and its neighbours (ORB-SLAM2's SearchInNeighbors + Fuse).
#include <cmath>
#include <unordered_set>

#include "feature/descriptor.h"
#include "map/keyframe.h"
#include "map/map_point.h"
#include "mapping/mapping_steps.h"

namespace esdslam {
namespace {

// Best keypoint of `keyframe` for the point projected at (u, v, right_u) with predicted level,
// among keypoints passing the chi2 reprojection test and not dynamic (late_dynamic: the
// keyframe's KeyFrame::late_dynamic(), may be null); -1 if none within TH_LOW.
int BestKeypointForPoint(const KeyFrame& keyframe, const std::vector<std::uint8_t>* late_dynamic,
                         const cv::Mat& descriptor, const Vec3& p_cam, int level, double radius_factor) {
  const FeatureSet& features = keyframe.features();
  const RgbdRig& rig = keyframe.rig();
  const Vec2 pixel = rig.camera.Project(p_cam);
  const double right_u = pixel.x() - rig.bf / p_cam.z();
  const double radius = radius_factor * rig.pyramid.scale_factors[level];
  int best = -1, best_distance = 256;
  for (int j : keyframe.FeaturesInArea(pixel.x(), pixel.y(), radius)) {
    const int keypoint_level = features.level(j);
    if (keypoint_level < level - 1 || keypoint_level > level || IsDynamicKeypoint(features, late_dynamic, j)) continue;
    const double inv_sigma2 = rig.pyramid.inv_level_sigma2[keypoint_level];
    double chi2 = (pixel - features.pixel(j)).squaredNorm() * inv_sigma2;
    if (features.right_u[j] >= 0) {
      const double er = right_u - features.right_u[j];
      if (chi2 + er * er * inv_sigma2 > 7.8) continue;
    } else if (chi2 > 5.99) {
      continue;
    }
    const int distance = DescriptorDistance(descriptor.ptr<unsigned char>(0), features.descriptor(j));
    if (distance < best_distance) best_distance = distance, best = j;
  }
  return best_distance <= kDescriptorDistanceLow ? best : -1;
}

}  // namespace

int FusePointsIntoKeyFrame(KeyFrame* keyframe, const std::vector<MapPoint*>& points, double radius_factor) {
  const Rigid3 cam_from_world = keyframe->cam_from_world();
  const Vec3 center = keyframe->camera_center();
  const RgbdRig& rig = keyframe->rig();
  const std::shared_ptr<const std::vector<std::uint8_t>> late_dynamic = keyframe->late_dynamic();
  int fused = 0;
  for (MapPoint* point : points) {
    if (point == nullptr || point->is_bad() || point->IsObservedBy(keyframe)) continue;
    const Vec3 position = point->position();
    const Vec3 p_cam = cam_from_world * position;
    if (p_cam.z() <= 0 || !rig.camera.InImage(rig.camera.Project(p_cam))) continue;
    const Vec3 ray = position - center;
    const double distance = ray.norm();
    if (distance < point->min_distance() || distance > point->max_distance()) continue;
    if (ray.dot(point->normal()) < 0.5 * distance) continue;
    const int level = point->PredictLevel(distance, rig.pyramid.num_levels, rig.pyramid.log_scale_factor);
    const cv::Mat descriptor = point->descriptor();
    if (descriptor.empty()) continue;
    const int best = BestKeypointForPoint(*keyframe, late_dynamic.get(), descriptor, p_cam, level, radius_factor);
    if (best < 0) continue;
    MapPoint* existing = keyframe->map_point(best);
    if (existing != nullptr && !existing->is_bad()) {
      if (existing->num_observations() > point->num_observations()) point->Replace(existing);
      else existing->Replace(point);
    } else {
      point->AddObservation(keyframe, best, keyframe->features().has_depth(best));
      keyframe->AddMapPoint(point, best);
    }
    ++fused;
  }
  return fused;
}

int FuseWithNeighbours(KeyFrame* keyframe, double radius_factor) {
  std::vector<KeyFrame*> targets;
  std::unordered_set<const KeyFrame*> chosen;
  const auto add_target = [&](KeyFrame* candidate) {
    if (candidate->is_bad() || candidate == keyframe || !chosen.insert(candidate).second) return;
    targets.push_back(candidate);
  };
  const std::vector<KeyFrame*> neighbours = keyframe->BestCovisibleKeyframes(10);
  for (KeyFrame* neighbour : neighbours) add_target(neighbour);
  for (KeyFrame* neighbour : neighbours)
    for (KeyFrame* second : neighbour->BestCovisibleKeyframes(5)) add_target(second);

  int fused = 0;
  for (KeyFrame* target : targets) fused += FusePointsIntoKeyFrame(target, keyframe->valid_map_points(), radius_factor);

  std::vector<MapPoint*> candidates;
  std::unordered_set<const MapPoint*> added;
  for (KeyFrame* target : targets)
    for (MapPoint* point : target->valid_map_points())
      if (added.insert(point).second) candidates.push_back(point);
  fused += FusePointsIntoKeyFrame(keyframe, candidates, radius_factor);

  for (MapPoint* point : keyframe->valid_map_points()) {
    point->ComputeDistinctiveDescriptor();
    point->UpdateNormalAndDepth();
  }
  keyframe->UpdateConnections();
  return fused;
}

}  // namespace esdslam
