#pragma once
// Voxel-grid downsampling: every occupied cubic voxel of side `voxel_size` keeps one point, the
// weighted mean of the points that fell into it (position and colour). Memory is proportional to
// the number of occupied voxels, so a map of a bounded space stays bounded however many frames
// feed it.

#include <cstdint>
#include <unordered_map>

#include "dense/point_cloud.h"

namespace esdslam {

// Index of the voxel holding `point` (voxel (i, j, k) = [i, i+1) x [j, j+1) x [k, k+1) times
// voxel_size), packed into 21 bits per axis: +-2^20 voxels per axis (+-10 km at 1 cm); points
// beyond share the border voxels.
std::uint64_t VoxelKey(const Eigen::Vector3f& point, double voxel_size);

class VoxelGrid {
 public:
  explicit VoxelGrid(double voxel_size);

  void Insert(const PointCloud& cloud);
  // weight > 0: e.g. the number of pixels a point already averages.
  void Insert(const Eigen::Vector3f& point, const Rgb8& color, float weight = 1.0f);
  // One point per occupied voxel, ordered by voxel key (deterministic).
  PointCloud Extract() const;
  std::size_t num_voxels() const { return voxels_.size(); }
  double voxel_size() const { return voxel_size_; }

 private:
  struct Accumulator {
    double x = 0, y = 0, z = 0;
    double r = 0, g = 0, b = 0;
    double weight = 0;
  };

  double voxel_size_;
  std::unordered_map<std::uint64_t, Accumulator> voxels_;
};

// Convenience: downsample a cloud in one call.
PointCloud VoxelDownsample(const PointCloud& cloud, double voxel_size);

}  // namespace esdslam
