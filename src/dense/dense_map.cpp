#include "dense/dense_map.h"

#include "dense/outlier_filter.h"
#include "dense/voxel_grid.h"

namespace esdslam {

DenseMap::DenseMap(const DenseOptions& options) : options_(options) { options_.Check(); }

void DenseMap::SetKeyframeCloud(long keyframe_id, PointCloud cloud_in_cam) {
  std::lock_guard<std::mutex> lock(mutex_);
  clouds_in_cam_[keyframe_id] = std::move(cloud_in_cam);
}

void DenseMap::RemoveKeyframe(long keyframe_id) {
  std::lock_guard<std::mutex> lock(mutex_);
  clouds_in_cam_.erase(keyframe_id);
}

std::size_t DenseMap::num_keyframes() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return clouds_in_cam_.size();
}

std::size_t DenseMap::num_stored_points() const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::size_t n = 0;
  for (const auto& entry : clouds_in_cam_) n += entry.second.size();
  return n;
}

std::vector<DenseMap::PosedCloud> DenseMap::PosedClouds(const std::map<long, Rigid3>& world_from_keyframe) const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<PosedCloud> out;
  for (const auto& [id, cloud] : clouds_in_cam_) {
    const auto pose = world_from_keyframe.find(id);
    if (pose == world_from_keyframe.end()) continue;
    out.push_back({pose->second.translation(), TransformCloud(cloud, pose->second)});
  }
  return out;
}

PointCloud DenseMap::BuildGlobalCloud(const std::map<long, Rigid3>& world_from_keyframe) const {
  VoxelGrid grid(options_.voxel_size);
  for (const PosedCloud& posed : PosedClouds(world_from_keyframe)) grid.Insert(posed.cloud_world);
  PointCloud global = grid.Extract();
  if (!options_.outlier_removal) return global;
  OutlierFilterOptions filter;
  filter.neighbors = options_.outlier_neighbors;
  filter.std_ratio = options_.outlier_std_ratio;
  filter.search_radius = 4.0 * options_.voxel_size;
  return RemoveStatisticalOutliers(global, filter);
}

}  // namespace esdslam
