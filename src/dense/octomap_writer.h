#pragma once
// OctoMap occupancy tree of the static map, for planners: every keyframe's rays (KeyframeRays,
// dynamic pixels left out) are inserted with ray casting from that keyframe's camera centre at
// its current pose, so the space between camera and surface is carved free (up to a noise margin
// before the reading) and surfaces become occupied; readings beyond
// DenseOptions::octomap_max_range only carve free space up to that range. Then the
// occupied cells get the dense points' free-space consistency (dense/free_space.h), keyframe by
// keyframe with the keyframes' ray depths: a cell later keyframes see through is set free.
// With a cloud given, an occupied cell holding fewer than DenseOptions::octomap_min_points of its
// points is set free too (the cloud has had the free-space consistency at every pixel of the
// keyframes, the tree only at the coarse rays).
// Resolution: DenseOptions::octomap_resolution. Written as a binary .bt file (OctoMap's own
// format, readable by octovis and octomap::OcTree::readBinary).

#include <string>

#include "dense/dense_map.h"

namespace esdslam {

struct OctomapStats {
  std::size_t leaf_nodes = 0;
  std::size_t occupied_leaves = 0;
  std::size_t free_leaves = 0;
  std::size_t rays = 0;
  std::size_t carved_cells = 0;  // occupied cells set free by later keyframes' free-space evidence
  std::size_t unsupported_cells = 0;  // occupied cells set free for holding too few cloud points
};

// Builds the tree from every keyframe of `map` at `poses` (resolved as DenseMap::Resolve does)
// and writes it to `path`. `cloud` (world frame, DenseMap::BuildGlobalCloud at the same poses)
// may be null: no point support check. Throws Error when the file cannot be written.
OctomapStats WriteOctomap(const std::string& path, const DenseMap& map, const KeyframePoses& poses,
                          const PointCloud* cloud = nullptr);

}  // namespace esdslam
