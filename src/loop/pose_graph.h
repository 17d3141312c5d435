#pragma once
// Pose-graph optimisation over the essential graph (ORB-SLAM2 loop correction, SE(3) since RGB-D
// fixes the scale). Nodes are keyframe poses cam_from_world keyed by keyframe id; an edge (i, j)
// measures cam_i_from_cam_j = T_i * T_j^-1 (T = cam_from_world). Residual of an edge, 6-vector:
//   E = measured^-1 * T_i * T_j^-1,  r = sqrt(weight) * [translation(E); 2 * vec(quaternion(E))]
// (first-order equal to Log(E), with w >= 0 on E's quaternion). Solved with Ceres
// (Levenberg-Marquardt, sparse Cholesky); fixed nodes keep their pose exactly.

#include <map>
#include <set>
#include <vector>

#include "common/geometry.h"

namespace esdslam {

struct PoseGraphEdge {
  long from = -1;  // keyframe id i
  long to = -1;    // keyframe id j
  Rigid3 from_from_to;  // measured cam_i_from_cam_j
  double weight = 1.0;  // information scale (> 0)
};

// Edge measured from two current poses: cam_i_from_cam_j = T_i * T_j^-1.
PoseGraphEdge RelativePoseEdge(long from, long to, const Rigid3& from_cam_from_world, const Rigid3& to_cam_from_world,
                               double weight = 1.0);

struct CovisibilityLink {
  long a = -1, b = -1;
  int weight = 0;  // map points both observe
};

// The essential graph's edges, measured from `cam_from_world`: spanning-tree edges (child ->
// parent), covisibility links with weight >= min_covisibility (each pair once, not already a
// tree edge), plus `loop_edges` as given. Ids missing from cam_from_world are skipped.
std::vector<PoseGraphEdge> EssentialGraphEdges(const std::map<long, Rigid3>& cam_from_world,
                                               const std::map<long, long>& parent_of,
                                               const std::vector<CovisibilityLink>& covisibility,
                                               const std::vector<PoseGraphEdge>& loop_edges,
                                               int min_covisibility = 100);

struct PoseGraphOptions {
  int max_iterations = 20;  // ORB-SLAM2 runs 20 Levenberg-Marquardt iterations
  bool log_summary = false;

  void Check() const;
};

struct PoseGraphResult {
  std::map<long, Rigid3> cam_from_world;  // every node, optimised (fixed ones unchanged)
  double initial_cost = 0.0;              // 0.5 * sum |r|^2
  double final_cost = 0.0;
  int iterations = 0;
};

// Throws Error when an edge names an unknown node, a weight is not positive or no node is fixed.
PoseGraphResult OptimizePoseGraph(const std::map<long, Rigid3>& cam_from_world, const std::vector<PoseGraphEdge>& edges,
                                  const std::set<long>& fixed_ids, const PoseGraphOptions& options = {});

// Moves each map point rigidly with its reference keyframe's correction:
//   p_new = world_from_cam_new(ref) * cam_from_world_old(ref) * p_old.
// Points whose reference keyframe is missing from either map are returned unchanged.
std::vector<Vec3> CorrectMapPoints(const std::vector<Vec3>& points_world, const std::vector<long>& reference_keyframe_ids,
                                   const std::map<long, Rigid3>& old_cam_from_world,
                                   const std::map<long, Rigid3>& new_cam_from_world);

}  // namespace esdslam
