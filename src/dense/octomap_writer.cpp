#include "dense/octomap_writer.h"

#include "common/error.h"
#include "dense/voxel_grid.h"

#ifdef ESDSLAM_HAVE_OCTOMAP
#include <octomap/OcTree.h>
#endif

namespace esdslam {

#ifdef ESDSLAM_HAVE_OCTOMAP
bool WriteOctomap(const std::string& path, const std::vector<DenseMap::PosedCloud>& clouds, double resolution,
                  double max_range, OctomapStats* stats) {
  octomap::OcTree tree(resolution);
  for (const DenseMap::PosedCloud& posed : clouds) {
    // One ray per occupied OctoMap cell is enough: thin the 1 cm cloud to the tree resolution.
    const PointCloud thinned = VoxelDownsample(posed.cloud_world, resolution);
    octomap::Pointcloud scan;
    scan.reserve(thinned.size());
    for (const auto& p : thinned.points) scan.push_back(p.x(), p.y(), p.z());
    const octomap::point3d origin(static_cast<float>(posed.sensor_origin_world.x()), static_cast<float>(posed.sensor_origin_world.y()),
                                  static_cast<float>(posed.sensor_origin_world.z()));
    tree.insertPointCloud(scan, origin, max_range, /*lazy_eval=*/false, /*discretize=*/true);
  }
  tree.updateInnerOccupancy();
  if (stats) {
    *stats = OctomapStats{};
    for (auto it = tree.begin_leafs(); it != tree.end_leafs(); ++it) {
      ++stats->leaf_nodes;
      if (tree.isNodeOccupied(*it)) ++stats->occupied_leaves; else ++stats->free_leaves;
    }
  }
  if (!tree.writeBinary(path)) throw InputError(path, 0, "cannot write the OctoMap file");
  return true;
}
#else
bool WriteOctomap(const std::string&, const std::vector<DenseMap::PosedCloud>&, double, double, OctomapStats*) {
  return false;
}
#endif

}  // namespace esdslam
