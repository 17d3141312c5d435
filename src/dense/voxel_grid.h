#pragma once
// Voxel-grid downsampling: every occupied cubic voxel of side `voxel_size` keeps one point, the
// mean of the points that fell into it (position and colour). Memory is proportional to the
// number of occupied voxels, so a map of a bounded space stays bounded however many frames
// feed it.

#include <cstdint>
#include <unordered_map>

#include "dense/point_cloud.h"

namespace esdslam {

class VoxelGrid {
 public:
  explicit VoxelGrid(double voxel_size);

  void Insert(const PointCloud& cloud);
  void Insert(const Eigen::Vector3f& point, const Rgb8& color);
  // One point per occupied voxel, ordered by voxel key (deterministic).
  PointCloud Extract() const;
  std::size_t num_voxels() const { return voxels_.size(); }
  double voxel_size() const { return voxel_size_; }

 private:
  struct Accumulator {
    double x = 0, y = 0, z = 0;
    std::uint32_t r = 0, g = 0, b = 0;
    std::uint32_t count = 0;
  };
  std::uint64_t Key(const Eigen::Vector3f& point) const;

  double voxel_size_;
  std::unordered_map<std::uint64_t, Accumulator> voxels_;
};

// Convenience: downsample a cloud in one call.
PointCloud VoxelDownsample(const PointCloud& cloud, double voxel_size);

}  // namespace esdslam
