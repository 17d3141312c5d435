#include "dense/dense_map.h"

#include <optional>

#include "dense/free_space.h"
#include "dense/outlier_filter.h"

namespace esdslam {

DenseMap::DenseMap(const PinholeCamera& camera, const DenseOptions& options)
    : options_(options), backprojector_(camera, options), points_(options.voxel_size, options.depth_noise_at_1m) {}

void DenseMap::Integrate(const DenseKeyframe& keyframe, const KeyframePoses& poses, bool behind) {
  KeyframeObservation observation = backprojector_.Observe(keyframe.bgr, keyframe.depth_m, keyframe.dynamic_mask);
  const auto given = poses.find(keyframe.id);
  const Rigid3 world_from_cam = given != poses.end() ? given->second : keyframe.world_from_cam;
  // Every valid reading is free-space evidence, masked or not: a person in front of a stored
  // point only occludes it.
  std::optional<FreeSpaceView> view;
  if (options_.free_space_carving) view.emplace(backprojector_.camera(), world_from_cam, keyframe.depth_m, 1, options_);
  std::lock_guard<std::mutex> lock(mutex_);
  keyframes_[keyframe.id] = KeyframeRecord{keyframe.timestamp, keyframe.world_from_cam, std::move(observation.rays)};
  const KeyframePoses resolved = ResolveLocked(poses);
  reindexed_anchors_ += points_.UpdatePoses(resolved, behind ? 1.0 : 0.25);
  if (view) points_.CarveFreeSpace(*view, options_.free_space_max_evidence);
  points_.Integrate(keyframe.id, world_from_cam, observation.points_cam);
}

KeyframePoses DenseMap::ResolveLocked(const KeyframePoses& poses) const {
  KeyframePoses resolved;
  for (const auto& [id, record] : keyframes_) {
    const auto given = poses.find(id);
    resolved.emplace_hint(resolved.end(), id, given != poses.end() ? given->second : record.handoff_world_from_cam);
  }
  return resolved;
}

KeyframePoses DenseMap::Resolve(const KeyframePoses& poses) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return ResolveLocked(poses);
}

PointCloud DenseMap::BuildGlobalCloud(const KeyframePoses& poses) const {
  PointCloud global;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const KeyframePoses resolved = ResolveLocked(poses);
    reindexed_anchors_ += points_.UpdatePoses(resolved);
    global = points_.Extract(resolved);
  }
  if (!options_.outlier_removal) return global;
  OutlierFilterOptions filter;
  filter.neighbors = options_.outlier_neighbors;
  filter.std_ratio = options_.outlier_std_ratio;
  filter.search_radius = 4.0 * options_.voxel_size;
  return RemoveStatisticalOutliers(global, filter);
}

std::vector<StampedPose> DenseMap::StampedPoses(const KeyframePoses& poses) const {
  std::lock_guard<std::mutex> lock(mutex_);
  const KeyframePoses resolved = ResolveLocked(poses);
  std::vector<StampedPose> out;
  for (const auto& [id, record] : keyframes_) out.push_back({record.timestamp, resolved.at(id)});
  return out;
}

std::vector<PosedRays> DenseMap::RaysAt(const KeyframePoses& poses) const {
  std::lock_guard<std::mutex> lock(mutex_);
  const KeyframePoses resolved = ResolveLocked(poses);
  std::vector<PosedRays> out;
  out.reserve(keyframes_.size());
  for (const auto& [id, record] : keyframes_) out.push_back({id, resolved.at(id), record.rays});
  return out;
}

DenseMapStats DenseMap::stats() const {
  std::lock_guard<std::mutex> lock(mutex_);
  DenseMapStats stats;
  stats.keyframes = keyframes_.size();
  stats.points = points_.num_points();
  stats.point_bytes = points_.memory_bytes();
  for (const auto& entry : keyframes_) stats.ray_bytes += entry.second.rays.bytes();
  stats.reindexed_anchors = reindexed_anchors_;
  stats.reindexed_points = points_.num_reindexed_points();
  stats.carved_points = points_.num_carved_points();
  return stats;
}

}  // namespace esdslam
