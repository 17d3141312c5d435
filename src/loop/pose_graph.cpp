#include "loop/pose_graph.h"

#include <cmath>
#include <memory>

#include <ceres/ceres.h>
#include <spdlog/spdlog.h>

#include "common/error.h"

namespace esdslam {
namespace {

// Parameters: quaternion (x, y, z, w; Eigen order) and translation of cam_from_world for i and j.
struct RelativePoseCost {
  RelativePoseCost(const Rigid3& measured, double weight)
      : measured_inverse_(measured.inverse()), sqrt_weight_(std::sqrt(weight)) {}

  template <typename T>
  bool operator()(const T* q_i_data, const T* t_i_data, const T* q_j_data, const T* t_j_data, T* residual) const {
    using Quaternion = Eigen::Quaternion<T>;
    using Vector3 = Eigen::Matrix<T, 3, 1>;
    const Eigen::Map<const Quaternion> q_i(q_i_data), q_j(q_j_data);
    const Eigen::Map<const Vector3> t_i(t_i_data), t_j(t_j_data);
    // T_i * T_j^-1 = (q_i q_j^*, t_i - q_i q_j^* t_j)
    const Quaternion q_ij = q_i * q_j.conjugate();
    const Vector3 t_ij = t_i - q_ij * t_j;
    const Quaternion q_m = measured_inverse_.rotation().cast<T>();
    const Vector3 t_m = measured_inverse_.translation().cast<T>();
    const Quaternion q_error = q_m * q_ij;
    const Vector3 t_error = q_m * t_ij + t_m;
    const T sign = q_error.w() < T(0) ? T(-1) : T(1);
    for (int k = 0; k < 3; ++k) {
      residual[k] = T(sqrt_weight_) * t_error[k];
      residual[3 + k] = T(sqrt_weight_) * T(2) * sign * q_error.vec()[k];
    }
    return true;
  }

  Rigid3 measured_inverse_;
  double sqrt_weight_;
};

struct NodeParameters {
  double quaternion[4];   // x, y, z, w
  double translation[3];
};

}  // namespace

void PoseGraphOptions::Check() const {
  if (max_iterations < 1) throw Error("pose graph: max_iterations must be positive");
}

PoseGraphEdge RelativePoseEdge(long from, long to, const Rigid3& from_cam_from_world, const Rigid3& to_cam_from_world,
                               double weight) {
  return {from, to, from_cam_from_world * to_cam_from_world.inverse(), weight};
}

std::vector<PoseGraphEdge> EssentialGraphEdges(const std::map<long, Rigid3>& cam_from_world,
                                               const std::map<long, long>& parent_of,
                                               const std::vector<CovisibilityLink>& covisibility,
                                               const std::vector<PoseGraphEdge>& loop_edges, int min_covisibility) {
  std::vector<PoseGraphEdge> edges;
  std::set<std::pair<long, long>> linked;  // (min id, max id)
  const auto add = [&](long a, long b) {
    const auto ia = cam_from_world.find(a), ib = cam_from_world.find(b);
    if (a == b || ia == cam_from_world.end() || ib == cam_from_world.end()) return;
    if (!linked.insert({std::min(a, b), std::max(a, b)}).second) return;
    edges.push_back(RelativePoseEdge(a, b, ia->second, ib->second));
  };
  for (const auto& [child, parent] : parent_of) add(child, parent);
  for (const CovisibilityLink& link : covisibility) {
    if (link.weight >= min_covisibility) add(link.a, link.b);
  }
  edges.insert(edges.end(), loop_edges.begin(), loop_edges.end());
  return edges;
}

PoseGraphResult OptimizePoseGraph(const std::map<long, Rigid3>& cam_from_world, const std::vector<PoseGraphEdge>& edges,
                                  const std::set<long>& fixed_ids, const PoseGraphOptions& options) {
  options.Check();
  std::map<long, NodeParameters> nodes;
  for (const auto& [id, pose] : cam_from_world) {
    NodeParameters& p = nodes[id];
    const Quat& q = pose.rotation();
    p.quaternion[0] = q.x(), p.quaternion[1] = q.y(), p.quaternion[2] = q.z(), p.quaternion[3] = q.w();
    for (int k = 0; k < 3; ++k) p.translation[k] = pose.translation()[k];
  }
  bool any_fixed = false;
  for (const long id : fixed_ids) any_fixed = any_fixed || nodes.count(id) > 0;
  if (!any_fixed) throw Error("pose graph: at least one node must be fixed (gauge freedom)");

  ceres::Problem problem;
  for (const PoseGraphEdge& edge : edges) {
    if (nodes.count(edge.from) == 0 || nodes.count(edge.to) == 0)
      throw Error(fmt::format("pose graph: edge {} -> {} names an unknown node", edge.from, edge.to));
    if (!(edge.weight > 0.0)) throw Error("pose graph: edge weights must be positive");
    if (edge.from == edge.to) continue;
    NodeParameters& i = nodes[edge.from];
    NodeParameters& j = nodes[edge.to];
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<RelativePoseCost, 6, 4, 3, 4, 3>(
                                 new RelativePoseCost(edge.from_from_to, edge.weight)),
                             nullptr, i.quaternion, i.translation, j.quaternion, j.translation);
  }
  for (auto& [id, p] : nodes) {
    if (!problem.HasParameterBlock(p.quaternion)) continue;
    problem.SetManifold(p.quaternion, new ceres::EigenQuaternionManifold());
    if (fixed_ids.count(id) > 0) {
      problem.SetParameterBlockConstant(p.quaternion);
      problem.SetParameterBlockConstant(p.translation);
    }
  }

  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  solver_options.max_num_iterations = options.max_iterations;
  solver_options.num_threads = 1;
  solver_options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);
  if (options.log_summary) spdlog::info("pose graph: {}", summary.BriefReport());

  PoseGraphResult result;
  result.initial_cost = summary.initial_cost;
  result.final_cost = summary.final_cost;
  result.iterations = static_cast<int>(summary.iterations.size());
  for (const auto& [id, p] : nodes) {
    const Quat q(p.quaternion[3], p.quaternion[0], p.quaternion[1], p.quaternion[2]);
    result.cam_from_world[id] = Rigid3(q, Vec3(p.translation[0], p.translation[1], p.translation[2]));
  }
  // Fixed nodes bypass the quaternion round trip so that they stay bit-identical.
  for (const long id : fixed_ids) {
    const auto it = cam_from_world.find(id);
    if (it != cam_from_world.end()) result.cam_from_world[id] = it->second;
  }
  return result;
}

std::vector<Vec3> CorrectMapPoints(const std::vector<Vec3>& points_world, const std::vector<long>& reference_keyframe_ids,
                                   const std::map<long, Rigid3>& old_cam_from_world,
                                   const std::map<long, Rigid3>& new_cam_from_world) {
  if (points_world.size() != reference_keyframe_ids.size())
    throw Error("CorrectMapPoints: one reference keyframe per point is required");
  std::vector<Vec3> corrected = points_world;
  for (std::size_t i = 0; i < points_world.size(); ++i) {
    const auto old_it = old_cam_from_world.find(reference_keyframe_ids[i]);
    const auto new_it = new_cam_from_world.find(reference_keyframe_ids[i]);
    if (old_it == old_cam_from_world.end() || new_it == new_cam_from_world.end()) continue;
    corrected[i] = new_it->second.inverse() * (old_it->second * points_world[i]);
  }
  return corrected;
}

}  // namespace esdslam
