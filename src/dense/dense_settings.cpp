#include "dense/dense_settings.h"

namespace esdslam {

void BindDenseSettings(DenseOptions& options, SettingsTable& table) {
  table.Add("Dense.voxelSize", &options.voxel_size);
  table.Add("Dense.minDepth", &options.min_depth);
  table.Add("Dense.maxDepth", &options.max_depth);
  table.Add("Dense.pixelStride", &options.pixel_stride);
  table.Add("Dense.maskDilation", &options.mask_dilation_px);
  table.Add("Dense.edgeFilter", &options.edge_filter_px);
  table.Add("Dense.edgeJumpRatio", &options.edge_jump_ratio);
  table.Add("Dense.depthNoiseAt1m", &options.depth_noise_at_1m);
  table.Add("Dense.outlierRemoval", &options.outlier_removal);
  table.Add("Dense.outlierNeighbors", &options.outlier_neighbors);
  table.Add("Dense.outlierStdRatio", &options.outlier_std_ratio);
  table.Add("Dense.octomapResolution", &options.octomap_resolution);
  table.Add("Dense.octomapMaxRange", &options.octomap_max_range);
  table.Add("Dense.writePcd", &options.write_pcd);
  table.Add("Dense.freeSpaceCarving", &options.free_space_carving);
  table.Add("Dense.freeSpaceSigmas", &options.free_space_sigmas);
  table.Add("Dense.freeSpaceMinMargin", &options.free_space_min_margin);
  table.Add("Dense.freeSpaceWindow", &options.free_space_window_px);
  table.Add("Dense.octomapCarveWindow", &options.octomap_carve_window_px);
  table.Add("Dense.freeSpaceMaxEvidence", &options.free_space_max_evidence);
  table.Add("Dense.octomapMinPoints", &options.octomap_min_points);
}

}  // namespace esdslam
