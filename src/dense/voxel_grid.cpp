#include "dense/voxel_grid.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "common/error.h"

namespace esdslam {

namespace {
// Voxel indices are packed into 21 bits each (offset so that negatives fit): +-1e6 voxels per
// axis, i.e. +-10 km at 1 cm.
constexpr std::int64_t kAxisOffset = 1 << 20;
constexpr std::uint64_t kAxisMask = (1u << 21) - 1;
}  // namespace

VoxelGrid::VoxelGrid(double voxel_size) : voxel_size_(voxel_size) {
  if (!(voxel_size > 0)) throw Error("VoxelGrid: voxel size must be positive");
}

std::uint64_t VoxelKey(const Eigen::Vector3f& point, double voxel_size) {
  std::uint64_t key = 0;
  for (int axis = 0; axis < 3; ++axis) {
    const auto index = static_cast<std::int64_t>(std::floor(point[axis] / voxel_size)) + kAxisOffset;
    key = (key << 21) | (static_cast<std::uint64_t>(std::clamp<std::int64_t>(index, 0, kAxisMask)) & kAxisMask);
  }
  return key;
}

void VoxelGrid::Insert(const Eigen::Vector3f& point, const Rgb8& color, float weight) {
  if (!point.allFinite() || !(weight > 0)) return;
  Accumulator& acc = voxels_[VoxelKey(point, voxel_size_)];
  acc.x += weight * point.x();
  acc.y += weight * point.y();
  acc.z += weight * point.z();
  acc.r += weight * color.r;
  acc.g += weight * color.g;
  acc.b += weight * color.b;
  acc.weight += weight;
}

void VoxelGrid::Insert(const PointCloud& cloud) {
  for (std::size_t i = 0; i < cloud.size(); ++i) Insert(cloud.points[i], cloud.colors[i]);
}

PointCloud VoxelGrid::Extract() const {
  std::vector<std::uint64_t> keys;
  keys.reserve(voxels_.size());
  for (const auto& entry : voxels_) keys.push_back(entry.first);
  std::sort(keys.begin(), keys.end());
  PointCloud cloud;
  cloud.reserve(keys.size());
  for (const std::uint64_t key : keys) {
    const Accumulator& acc = voxels_.at(key);
    const double n = acc.weight;
    const auto channel = [n](double sum) { return static_cast<std::uint8_t>(std::clamp(std::lround(sum / n), 0L, 255L)); };
    cloud.push_back(Eigen::Vector3f(static_cast<float>(acc.x / n), static_cast<float>(acc.y / n), static_cast<float>(acc.z / n)),
                    Rgb8{channel(acc.r), channel(acc.g), channel(acc.b)});
  }
  return cloud;
}

PointCloud VoxelDownsample(const PointCloud& cloud, double voxel_size) {
  VoxelGrid grid(voxel_size);
  grid.Insert(cloud);
  return grid.Extract();
}

PointCloud TransformCloud(const PointCloud& cloud, const Rigid3& to_from_cloud) {
  const Eigen::Matrix3f rotation = to_from_cloud.rotation_matrix().cast<float>();
  const Eigen::Vector3f translation = to_from_cloud.translation().cast<float>();
  PointCloud out;
  out.colors = cloud.colors;
  out.points.resize(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) out.points[i] = rotation * cloud.points[i] + translation;
  return out;
}

}  // namespace esdslam
