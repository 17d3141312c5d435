#pragma once
// Settings of the static dense map (keys Dense.* in the settings file).

#include "common/setting_error.h"

namespace esdslam {

struct DenseOptions {
  double voxel_size = 0.01;           // m: global map resolution (and per-keyframe cloud resolution)
  double min_depth = 0.2;             // m: closer depth readings are ignored
  double max_depth = 4.0;             // m: farther readings are ignored (RGB-D noise grows with z^2)
  int pixel_stride = 2;               // back-project every n-th pixel in u and v
  int mask_dilation_px = 7;           // dynamic masks are grown by this many pixels before use
  // Depth edges: a pixel with a neighbour within edgeFilter px whose depth is farther by more
  // than edgeJumpRatio * z (the foreground side of a silhouette, and mixed pixels between) is
  // left out of the dense cloud (the OctoMap keeps it: its cells are coarser). RGB-D sensors smear depth
  // across silhouettes (mixed pixels, foreground fattening), which another view then sees
  // through; the same surface seen from elsewhere is away from a silhouette.
  int edge_filter_px = 2;             // 0 = off
  double edge_jump_ratio = 0.05;
  // m: depth noise sigma at 1 m, sigma(z) = depthNoiseAt1m * z^2 (Kinect v1 / Xtion: about 1.4e-3,
  // Khoshelham and Elberink 2012); readings within 2 sigma of a point on their ray merge into it.
  double depth_noise_at_1m = 0.0015;
  bool outlier_removal = true;        // statistical outlier removal on the global cloud
  int outlier_neighbors = 8;          // k nearest neighbours for the mean-distance statistic
  double outlier_std_ratio = 2.0;     // drop points whose mean k-NN distance > mean + ratio * std
  double octomap_resolution = 0.05;   // m: OctoMap leaf size
  double octomap_max_range = 4.0;     // m: rays are cut at this length when carving free space
  bool write_pcd = false;             // also write dense.pcd (PCL) next to dense.ply
  // Free-space consistency (dense/free_space.h): a stored point or occupied OctoMap cell that a
  // later keyframe sees through by more than max(freeSpaceMinMargin, freeSpaceSigmas * sigma(z))
  // loses evidence; at none it is removed. Evidence grows by one per keyframe that sees it, up to
  // freeSpaceMaxEvidence keyframes that must see through it before it goes.
  bool free_space_carving = true;
  double free_space_sigmas = 3.0;       // depth-noise sigmas
  double free_space_min_margin = 0.03;  // m
  int free_space_window_px = 2;         // carve only where the whole (2n+1)^2 neighbourhood sees past
  int free_space_max_evidence = 2;      // keyframes
  // An occupied OctoMap cell must hold at least this many points of the final cloud (after the
  // free-space consistency and the edge filter): a cell only coarse ray endpoints support, at a
  // silhouette the keyframes' rays do not see past, is set free. 0 = off (the default: on Bonn
  // 1 point lowered cell ghosts 0.79 -> 0.69 % but wall coverage 98.4 -> 97.6 %; docs/RESULTS.md).
  int octomap_min_points = 0;
  // The neighbourhood an occupied OctoMap cell's see-through test needs (free_space_window_px for
  // the cells). Their test runs on the keyframes' coarse rays, one every pixelStride pixels, where
  // any window > 0 is at least one ray on each side (12 px at stride 6, more than a 5 cm cell at
  // 3 m): 0 = the ray nearest the cell centre's projection alone (default; with a cell seen through
  // only past its whole diagonal, octomap_writer.cpp). On Bonn: cell ghosts 0.66 -> 0.44 %, wall
  // coverage unchanged (docs/RESULTS.md). -1 = free_space_window_px.
  int octomap_carve_window_px = 0;

  // Throws SettingError naming the Dense.* key of a value outside its plausible range. The
  // voxel bounds keep the map's cell count and the ray walks finite (1 mm .. 1 m).
  void Check() const {
    CheckRange("Dense.voxelSize", voxel_size, 0.001, 1.0, "m");
    CheckRange("Dense.minDepth", min_depth, 0.0, 100.0, "m");
    CheckRange("Dense.maxDepth", max_depth, min_depth + 0.01, 100.0, "m");
    CheckRange("Dense.pixelStride", pixel_stride, 1, 64, "px");
    CheckRange("Dense.maskDilation", mask_dilation_px, 0, 200, "px");
    CheckRange("Dense.edgeFilter", edge_filter_px, 0, 10, "px");
    CheckRange("Dense.edgeJumpRatio", edge_jump_ratio, 1e-3, 1.0);
    CheckRange("Dense.depthNoiseAt1m", depth_noise_at_1m, 0.0, 0.05, "m");
    CheckRange("Dense.outlierNeighbors", outlier_neighbors, 1, 100);
    CheckRange("Dense.outlierStdRatio", outlier_std_ratio, 0.1, 100.0);
    CheckRange("Dense.octomapResolution", octomap_resolution, 0.005, 2.0, "m");
    CheckRange("Dense.octomapMaxRange", octomap_max_range, 0.1, 100.0, "m");
    CheckRange("Dense.freeSpaceSigmas", free_space_sigmas, 1.0, 10.0);
    CheckRange("Dense.freeSpaceMinMargin", free_space_min_margin, 1e-3, 1.0, "m");
    CheckRange("Dense.freeSpaceWindow", free_space_window_px, 0, 10, "px");
    CheckRange("Dense.freeSpaceMaxEvidence", free_space_max_evidence, 1, 100);
    CheckRange("Dense.octomapMinPoints", octomap_min_points, 0, 1000, "points");
    CheckRange("Dense.octomapCarveWindow", octomap_carve_window_px, -1, 10, "px (-1 = Dense.freeSpaceWindow)");
  }
};

}  // namespace esdslam
