#include "dense/octomap_writer.h"

#include <octomap/OcTree.h>

#include "common/error.h"

namespace esdslam {

OctomapStats WriteOctomap(const std::string& path, const DenseMap& map, const KeyframePoses& poses) {
  const DenseOptions& options = map.options();
  octomap::OcTree tree(options.octomap_resolution);
  OctomapStats stats;
  for (const PosedRays& posed : map.RaysAt(poses)) {
    const Eigen::Matrix3f rotation = posed.world_from_cam.rotation_matrix().cast<float>();
    const Eigen::Vector3f origin = posed.world_from_cam.translation().cast<float>();
    octomap::Pointcloud scan;
    for (const Eigen::Vector3f& endpoint_cam : map.RayEndpoints(posed.rays)) {
      const Eigen::Vector3f p = rotation * endpoint_cam + origin;
      scan.push_back(p.x(), p.y(), p.z());
    }
    stats.rays += scan.size();
    // discretize: one ray per distinct end cell, as in OctoMap's own tools.
    tree.insertPointCloud(scan, octomap::point3d(origin.x(), origin.y(), origin.z()), options.octomap_max_range,
                          /*lazy_eval=*/false, /*discretize=*/true);
  }
  tree.updateInnerOccupancy();
  for (auto it = tree.begin_leafs(); it != tree.end_leafs(); ++it) {
    ++stats.leaf_nodes;
    if (tree.isNodeOccupied(*it)) ++stats.occupied_leaves;
    else ++stats.free_leaves;
  }
  if (!tree.writeBinary(path)) throw InputError(path, 0, "cannot write the OctoMap file");
  return stats;
}

}  // namespace esdslam
