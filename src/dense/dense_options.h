#pragma once
// Settings of the static dense map (keys Dense.* in the settings file).

#include "common/error.h"

namespace esdslam {

struct DenseOptions {
  double voxel_size = 0.01;           // m: global map resolution (and per-keyframe cloud resolution)
  double min_depth = 0.2;             // m: closer depth readings are ignored
  double max_depth = 4.0;             // m: farther readings are ignored (RGB-D noise grows with z^2)
  int pixel_stride = 2;               // back-project every n-th pixel in u and v
  int mask_dilation_px = 7;           // dynamic masks are grown by this many pixels before use
  // m: depth noise sigma at 1 m, sigma(z) = depthNoiseAt1m * z^2 (Kinect v1 / Xtion: about 1.4e-3,
  // Khoshelham and Elberink 2012); readings within 2 sigma of a point on their ray merge into it.
  double depth_noise_at_1m = 0.0015;
  bool outlier_removal = true;        // statistical outlier removal on the global cloud
  int outlier_neighbors = 8;          // k nearest neighbours for the mean-distance statistic
  double outlier_std_ratio = 2.0;     // drop points whose mean k-NN distance > mean + ratio * std
  double octomap_resolution = 0.05;   // m: OctoMap leaf size
  double octomap_max_range = 4.0;     // m: rays are cut at this length when carving free space
  bool write_pcd = false;             // also write dense.pcd (PCL) next to dense.ply

  void Check() const {
    if (!(voxel_size > 0)) throw Error("Dense.voxelSize must be positive");
    if (!(min_depth >= 0) || !(max_depth > min_depth)) throw Error("Dense depth range must satisfy 0 <= minDepth < maxDepth");
    if (pixel_stride < 1) throw Error("Dense.pixelStride must be >= 1");
    if (mask_dilation_px < 0) throw Error("Dense.maskDilation must be >= 0");
    if (!(depth_noise_at_1m >= 0) || depth_noise_at_1m > 0.05) throw Error("Dense.depthNoiseAt1m must be in [0, 0.05]");
    if (outlier_neighbors < 1) throw Error("Dense.outlierNeighbors must be >= 1");
    if (!(outlier_std_ratio > 0)) throw Error("Dense.outlierStdRatio must be positive");
    if (!(octomap_resolution > 0)) throw Error("Dense.octomapResolution must be positive");
    if (!(octomap_max_range > 0)) throw Error("Dense.octomapMaxRange must be positive");
  }
};

}  // namespace esdslam
