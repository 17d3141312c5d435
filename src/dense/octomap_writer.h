#pragma once
// OctoMap occupancy tree of the static map, for planners: every keyframe's cloud is inserted
// with ray casting from that keyframe's camera centre, so the space between camera and surface
// is carved free and surfaces become occupied. Written as a binary .bt file (OctoMap's own
// format, readable by octovis and octomap::OcTree::readBinary).

#include <string>
#include <vector>

#include "dense/dense_map.h"

namespace esdslam {

struct OctomapStats {
  std::size_t leaf_nodes = 0;
  std::size_t occupied_leaves = 0;
  std::size_t free_leaves = 0;
};

// Returns false (and writes nothing) when the build has no OctoMap support.
bool WriteOctomap(const std::string& path, const std::vector<DenseMap::PosedCloud>& clouds, double resolution,
                  double max_range, OctomapStats* stats = nullptr);

}  // namespace esdslam
