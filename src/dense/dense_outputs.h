#pragma once
// The dense map's output files, written from a DenseMap at given keyframe poses:
// dir/dense.ply (binary, coloured), dir/dense.pcd (optional: Dense.writePcd), dir/octomap.bt and two pictures,
// dir/dense_top.png and dir/dense_view.png (dense/map_render.h).

#include <string>

#include "dense/dense_map.h"

namespace esdslam {

struct DenseOutputFiles {
  bool ply = true;
  bool pcd = false;  // also when DenseOptions::write_pcd
  bool octomap = true;
  bool pictures = true;
};

struct DenseOutputSummary {
  std::size_t points = 0;
  std::size_t keyframes = 0;
  std::size_t occupied_leaves = 0;
  std::size_t free_leaves = 0;
  double cloud_ms = 0;    // global cloud: re-voxelising at the poses + outlier removal
  double octomap_ms = 0;  // ray casting + writing octomap.bt
  double build_ms = 0;    // everything, files included
};

DenseOutputSummary WriteDenseOutputs(const DenseMap& map, const KeyframePoses& poses, const std::string& dir,
                                     const DenseOutputFiles& files = {});

}  // namespace esdslam
