#include "dense/octomap_writer.h"

#include <algorithm>
#include <unordered_map>
#include <vector>

#include <octomap/OcTree.h>

#include "common/error.h"
#include "dense/free_space.h"

namespace esdslam {

namespace {

octomap::point3d ToOcto(const Eigen::Vector3f& p) { return octomap::point3d(p.x(), p.y(), p.z()); }

// One keyframe's rays as one OctoMap scan update (each cell updated once per keyframe, occupied
// winning over free, as OcTree::insertPointCloud does). Free space is carved up to `margin` before
// each reading (one cell or two sigma of its depth noise, whichever is larger): without it, rays
// grazing a surface from later keyframes carve away the cells that earlier readings of that
// surface marked occupied. Returns the number of rays.
std::size_t InsertKeyframeRays(octomap::OcTree* tree, const DenseMap& map, const PosedRays& posed) {
  const DenseOptions& options = map.options();
  const float resolution = static_cast<float>(options.octomap_resolution);
  const float max_range = static_cast<float>(options.octomap_max_range);
  const Eigen::Matrix3f rotation = posed.world_from_cam.rotation_matrix().cast<float>();
  const Eigen::Vector3f origin = posed.world_from_cam.translation().cast<float>();
  octomap::KeySet free_cells, occupied_cells;
  octomap::KeyRay ray;
  const std::vector<Eigen::Vector3f> endpoints = map.RayEndpoints(posed.rays);
  for (const Eigen::Vector3f& endpoint_cam : endpoints) {
    const Eigen::Vector3f direction = rotation * endpoint_cam;
    const float range = direction.norm();
    const float sigma = static_cast<float>(options.depth_noise_at_1m) * endpoint_cam.z() * endpoint_cam.z();
    const float margin = std::max(resolution, 2.0f * sigma);
    const bool surface = range <= max_range;
    const float free_length = surface ? range - margin : max_range;
    if (free_length > 0 && tree->computeRayKeys(ToOcto(origin), ToOcto(origin + direction * (free_length / range)), ray))
      free_cells.insert(ray.begin(), ray.end());
    octomap::OcTreeKey key;
    if (surface && tree->coordToKeyChecked(ToOcto(origin + direction), key)) occupied_cells.insert(key);
  }
  for (const octomap::OcTreeKey& key : free_cells)
    if (occupied_cells.find(key) == occupied_cells.end()) tree->updateNode(key, false, /*lazy_eval=*/true);
  for (const octomap::OcTreeKey& key : occupied_cells) tree->updateNode(key, true, /*lazy_eval=*/true);
  return endpoints.size();
}

// Free-space consistency of the occupied cells (dense/free_space.h), keyframe by keyframe in id
// order with the keyframes' ray depths: a cell that later keyframes see through loses its
// evidence and is set free. The see-through test of a cell looks at the ray nearest its centre's
// projection only (DenseOptions::octomap_carve_window_px, default 0): the rays are one every
// pixelStride pixels, so a neighbourhood of rays spans more than a cell at the silhouettes where
// the ghost cells are. Returns the number of cells freed.
std::size_t CarveOccupiedCells(octomap::OcTree* tree, const DenseMap& map, const std::vector<PosedRays>& keyframes) {
  std::vector<octomap::OcTreeKey> keys;
  std::vector<Eigen::Vector3f> centres;
  for (auto it = tree->begin_leafs(); it != tree->end_leafs(); ++it) {
    if (!tree->isNodeOccupied(*it)) continue;
    keys.push_back(it.getKey());
    const octomap::point3d c = it.getCoordinate();
    centres.emplace_back(c.x(), c.y(), c.z());
  }
  // A cell is seen through only past its whole diagonal (beyond the noise margin): the surface
  // that made it occupied can sit anywhere in it, and a ray that passes the cell's centre beside
  // that surface can meet the neighbouring cell's.
  const float extent = 1.73f * static_cast<float>(tree->getResolution());
  const int max_evidence = map.options().free_space_max_evidence;
  std::vector<std::uint8_t> evidence(keys.size(), 0);
  std::vector<bool> freed(keys.size(), false);
  DenseOptions options = map.options();
  if (options.octomap_carve_window_px >= 0) options.free_space_window_px = options.octomap_carve_window_px;
  for (const PosedRays& posed : keyframes) {
    cv::Mat depth_m;
    posed.rays.depth_mm.convertTo(depth_m, CV_32F, 0.001);
    const FreeSpaceView view(map.camera(), posed.world_from_cam, depth_m, posed.rays.stride, options);
    for (std::size_t i = 0; i < keys.size(); ++i) {
      const FreeSpaceVerdict verdict = view.Classify(centres[i], extent);
      if (!UpdateEvidence(verdict, max_evidence, &evidence[i])) freed[i] = true;
      if (verdict == FreeSpaceVerdict::kSeen) freed[i] = false;  // seen again: a surface again
    }
  }
  std::size_t count = 0;
  for (std::size_t i = 0; i < keys.size(); ++i)
    if (freed[i]) {
      tree->setNodeValue(keys[i], tree->getClampingThresMinLog(), /*lazy_eval=*/true);
      ++count;
    }
  return count;
}

// Occupied cells holding fewer than `min_points` points of `cloud` are set free. Returns how many.
std::size_t FreeUnsupportedCells(octomap::OcTree* tree, const PointCloud& cloud, int min_points) {
  std::unordered_map<octomap::OcTreeKey, int, octomap::OcTreeKey::KeyHash> points_per_cell;
  for (const Eigen::Vector3f& p : cloud.points) {
    octomap::OcTreeKey key;
    if (tree->coordToKeyChecked(ToOcto(p), key)) ++points_per_cell[key];
  }
  std::vector<octomap::OcTreeKey> unsupported;
  for (auto it = tree->begin_leafs(); it != tree->end_leafs(); ++it) {
    if (!tree->isNodeOccupied(*it)) continue;
    const auto found = points_per_cell.find(it.getKey());
    if (found == points_per_cell.end() || found->second < min_points) unsupported.push_back(it.getKey());
  }
  for (const octomap::OcTreeKey& key : unsupported)
    tree->setNodeValue(key, tree->getClampingThresMinLog(), /*lazy_eval=*/true);
  return unsupported.size();
}

}  // namespace

OctomapStats WriteOctomap(const std::string& path, const DenseMap& map, const KeyframePoses& poses,
                          const PointCloud* cloud) {
  octomap::OcTree tree(map.options().octomap_resolution);
  OctomapStats stats;
  const std::vector<PosedRays> keyframes = map.RaysAt(poses);
  for (const PosedRays& posed : keyframes) stats.rays += InsertKeyframeRays(&tree, map, posed);
  if (map.options().free_space_carving) stats.carved_cells = CarveOccupiedCells(&tree, map, keyframes);
  if (cloud && map.options().octomap_min_points > 0)
    stats.unsupported_cells = FreeUnsupportedCells(&tree, *cloud, map.options().octomap_min_points);
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
