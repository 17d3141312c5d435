#include "optim/schur_lm.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Cholesky>

#include "optim/levenberg_marquardt.h"

namespace esdslam {

namespace {

using Mat63 = Eigen::Matrix<double, 6, 3>;

// Which blocks are optimised and which observations enter. Slots number the free blocks that
// at least one inlier touches; -1 marks a fixed or untouched block.
struct Layout {
  std::vector<int> pose_slot;                 // keyframe -> free pose slot
  std::vector<int> point_slot;                // point -> free point slot
  std::vector<int> inliers;                   // observation indices that enter
  std::vector<std::vector<int>> point_terms;  // free point slot -> positions in `inliers`
  std::vector<int> pose_of_slot;              // free pose slot -> keyframe
  std::vector<int> point_of_slot;             // free point slot -> point
};

Layout MakeLayout(const BaProblem& problem) {
  Layout layout;
  layout.pose_slot.assign(problem.keyframes.size(), -1);
  layout.point_slot.assign(problem.points.size(), -1);
  for (size_t i = 0; i < problem.observations.size(); ++i) {
    const BaObservation& o = problem.observations[i];
    if (o.outlier) continue;
    const int position = static_cast<int>(layout.inliers.size());
    layout.inliers.push_back(static_cast<int>(i));
    if (!problem.keyframes[o.keyframe].fixed && layout.pose_slot[o.keyframe] < 0) {
      layout.pose_slot[o.keyframe] = static_cast<int>(layout.pose_of_slot.size());
      layout.pose_of_slot.push_back(o.keyframe);
    }
    if (problem.points[o.point].fixed) continue;
    if (layout.point_slot[o.point] < 0) {
      layout.point_slot[o.point] = static_cast<int>(layout.point_of_slot.size());
      layout.point_of_slot.push_back(o.point);
      layout.point_terms.emplace_back();
    }
    layout.point_terms[layout.point_slot[o.point]].push_back(position);
  }
  return layout;
}

// Gauss-Newton normal equations at one estimate: H = J^T W J and b = -J^T W r, by blocks.
struct NormalEquations {
  double cost = 0;
  std::vector<Mat6> pose_h;
  std::vector<Vec6> pose_b;
  std::vector<Mat3> point_h;
  std::vector<Vec3> point_b;
  std::vector<Mat63> coupling;  // per inlier position: J_pose^T W J_point (zero unless both free)
};

// Huber threshold of an observation (whitened px); +inf without the robust loss.
double DeltaOf(const SchurLmOptions& options, bool stereo) {
  if (!options.robust) return std::numeric_limits<double>::infinity();
  return stereo ? options.huber_delta_stereo : options.huber_delta_mono;
}

template <int R>
bool AccumulateTerm(const StereoIntrinsics& k, const BaObservation& o, const SchurLmOptions& options,
                    const BaState& state, int pose_slot, int point_slot, int position, NormalEquations* ne) {
  Eigen::Matrix<double, R, 1> r;
  Eigen::Matrix<double, R, 6> jp;
  Eigen::Matrix<double, R, 3> jl;
  if (!EvaluateReprojection<R>(k, BaMeasurement(o), state.poses[o.keyframe].data(), state.points[o.point], &r, &jp, &jl)) return false;
  double weight = 1;
  ne->cost += 0.5 * HuberRho(r.squaredNorm(), DeltaOf(options, R == 3), &weight);
  if (pose_slot >= 0) {
    ne->pose_h[pose_slot].noalias() += weight * jp.transpose() * jp;
    ne->pose_b[pose_slot].noalias() -= weight * jp.transpose() * r;
  }
  if (point_slot >= 0) {
    ne->point_h[point_slot].noalias() += weight * jl.transpose() * jl;
    ne->point_b[point_slot].noalias() -= weight * jl.transpose() * r;
  }
  if (pose_slot >= 0 && point_slot >= 0) ne->coupling[position].noalias() = weight * jp.transpose() * jl;
  return true;
}

// Fills *ne at `state`; false if an inlier is behind its camera.
bool Linearize(const StereoIntrinsics& k, const BaProblem& problem, const Layout& layout,
               const SchurLmOptions& options, const BaState& state, NormalEquations* ne) {
  ne->cost = 0;
  ne->pose_h.assign(layout.pose_of_slot.size(), Mat6::Zero());
  ne->pose_b.assign(layout.pose_of_slot.size(), Vec6::Zero());
  ne->point_h.assign(layout.point_of_slot.size(), Mat3::Zero());
  ne->point_b.assign(layout.point_of_slot.size(), Vec3::Zero());
  ne->coupling.assign(layout.inliers.size(), Mat63::Zero());
  for (size_t position = 0; position < layout.inliers.size(); ++position) {
    const BaObservation& o = problem.observations[layout.inliers[position]];
    const int pose_slot = layout.pose_slot[o.keyframe], point_slot = layout.point_slot[o.point];
    const int p = static_cast<int>(position);
    const bool ok = o.right_u >= 0 ? AccumulateTerm<3>(k, o, options, state, pose_slot, point_slot, p, ne)
                                   : AccumulateTerm<2>(k, o, options, state, pose_slot, point_slot, p, ne);
    if (!ok) return false;
  }
  return true;
}

// Cost at `state`; +inf if an inlier is behind its camera.
double Cost(const StereoIntrinsics& k, const BaProblem& problem, const Layout& layout, const SchurLmOptions& options,
            const BaState& state) {
  double cost = 0, weight = 1;
  for (const int index : layout.inliers) {
    const BaObservation& o = problem.observations[index];
    double squared = 0;
    if (o.right_u >= 0) {
      Eigen::Matrix<double, 3, 1> r;
      if (!EvaluateReprojection<3>(k, BaMeasurement(o), state.poses[o.keyframe].data(), state.points[o.point], &r, nullptr, nullptr))
        return std::numeric_limits<double>::infinity();
      squared = r.squaredNorm();
    } else {
      Eigen::Matrix<double, 2, 1> r;
      if (!EvaluateReprojection<2>(k, BaMeasurement(o), state.poses[o.keyframe].data(), state.points[o.point], &r, nullptr, nullptr))
        return std::numeric_limits<double>::infinity();
      squared = r.squaredNorm();
    }
    cost += 0.5 * HuberRho(squared, DeltaOf(options, o.right_u >= 0), &weight);
  }
  return cost;
}

struct Step {
  std::vector<Vec6> pose;   // per free pose slot, tangent
  std::vector<Vec3> point;  // per free point slot, m
};

// Reduced camera system S dx_pose = rhs: S = H_pp + D_p - sum over points of W V^-1 W^T,
// rhs = b_p - sum of W V^-1 b_l, with V = H_ll + D_l. Only S's lower triangle is filled.
void ReduceToPoses(const NormalEquations& ne, const Layout& layout, const BaProblem& problem, double lambda,
                   const std::vector<Mat3>& point_v_inverse, Eigen::MatrixXd* s, Eigen::VectorXd* rhs) {
  const int free_poses = static_cast<int>(layout.pose_of_slot.size());
  s->setZero(6 * free_poses, 6 * free_poses);
  rhs->resize(6 * free_poses);
  for (int a = 0; a < free_poses; ++a) {
    s->block<6, 6>(6 * a, 6 * a) = ne.pose_h[a];
    s->block<6, 6>(6 * a, 6 * a).diagonal() += LmDamping(ne.pose_h[a], lambda);
    rhs->segment<6>(6 * a) = ne.pose_b[a];
  }
  for (size_t l = 0; l < layout.point_terms.size(); ++l) {
    const std::vector<int>& terms = layout.point_terms[l];
    for (const int i : terms) {
      const int a = layout.pose_slot[problem.observations[layout.inliers[i]].keyframe];
      if (a < 0) continue;
      const Mat63 y = ne.coupling[i] * point_v_inverse[l];
      rhs->segment<6>(6 * a).noalias() -= y * ne.point_b[l];
      for (const int j : terms) {
        const int c = layout.pose_slot[problem.observations[layout.inliers[j]].keyframe];
        if (c < 0 || c > a) continue;
        s->block<6, 6>(6 * a, 6 * c).noalias() -= y * ne.coupling[j].transpose();
      }
    }
  }
}

// Solves the damped system; false if the reduced system is not positive definite.
bool SolveDamped(const NormalEquations& ne, const Layout& layout, const BaProblem& problem, double lambda,
                 Step* step, double* model_decrease) {
  const size_t free_points = layout.point_of_slot.size(), free_poses = layout.pose_of_slot.size();
  std::vector<Mat3> v_inverse(free_points);
  std::vector<Vec3> point_damping(free_points);
  for (size_t l = 0; l < free_points; ++l) {
    point_damping[l] = LmDamping(ne.point_h[l], lambda);
    Mat3 v = ne.point_h[l];
    v.diagonal() += point_damping[l];
    v_inverse[l] = v.inverse();
  }
  Eigen::MatrixXd s;
  Eigen::VectorXd rhs;
  ReduceToPoses(ne, layout, problem, lambda, v_inverse, &s, &rhs);
  Eigen::VectorXd pose_step = Eigen::VectorXd::Zero(rhs.size());
  if (rhs.size() > 0) {
    const Eigen::LLT<Eigen::MatrixXd, Eigen::Lower> cholesky(s);
    if (cholesky.info() != Eigen::Success) return false;
    pose_step = cholesky.solve(rhs);
    if (!pose_step.allFinite()) return false;
  }
  step->pose.resize(free_poses);
  *model_decrease = 0;
  for (size_t a = 0; a < free_poses; ++a) {
    step->pose[a] = pose_step.segment<6>(6 * a);
    const Vec6 damping = LmDamping(ne.pose_h[a], lambda);
    *model_decrease += step->pose[a].dot(ne.pose_b[a] + damping.cwiseProduct(step->pose[a]));
  }
  step->point.resize(free_points);
  for (size_t l = 0; l < free_points; ++l) {
    Vec3 b = ne.point_b[l];
    for (const int i : layout.point_terms[l]) {
      const int a = layout.pose_slot[problem.observations[layout.inliers[i]].keyframe];
      if (a >= 0) b.noalias() -= ne.coupling[i].transpose() * step->pose[a];
    }
    step->point[l] = v_inverse[l] * b;
    if (!step->point[l].allFinite()) return false;
    *model_decrease += step->point[l].dot(ne.point_b[l] + point_damping[l].cwiseProduct(step->point[l]));
  }
  // (H + D) dx = b, so the quadratic model falls by dx.b - dx.H.dx / 2 = (dx.b + dx.D.dx) / 2.
  *model_decrease *= 0.5;
  return true;
}

BaState Apply(const BaState& state, const Layout& layout, const Step& step) {
  BaState next = state;
  const PoseManifold manifold;
  for (size_t a = 0; a < step.pose.size(); ++a) {
    const int keyframe = layout.pose_of_slot[a];
    manifold.Plus(state.poses[keyframe].data(), step.pose[a].data(), next.poses[keyframe].data());
  }
  for (size_t l = 0; l < step.point.size(); ++l) next.points[layout.point_of_slot[l]] += step.point[l];
  return next;
}

// Ceres' parameter tolerance: |dx| <= tol * (|x| + tol) over the free blocks.
bool StepIsTiny(const BaState& state, const Layout& layout, const Step& step, double tolerance) {
  double x_squared = 0, step_squared = 0;
  for (size_t a = 0; a < step.pose.size(); ++a) {
    const auto& pose = state.poses[layout.pose_of_slot[a]];
    for (const double value : pose) x_squared += value * value;
    step_squared += step.pose[a].squaredNorm();
  }
  for (size_t l = 0; l < step.point.size(); ++l) {
    x_squared += state.points[layout.point_of_slot[l]].squaredNorm();
    step_squared += step.point[l].squaredNorm();
  }
  return std::sqrt(step_squared) <= tolerance * (std::sqrt(x_squared) + tolerance);
}

// The window as MinimizeLm's Problem (levenberg_marquardt.h).
class SchurBaProblem {
 public:
  using State = BaState;
  using Linearization = NormalEquations;
  using Step = esdslam::Step;

  SchurBaProblem(const StereoIntrinsics& k, const BaProblem& problem, const SchurLmOptions& options)
      : k_(k), problem_(problem), options_(options), layout_(MakeLayout(problem)) {}

  bool empty() const { return layout_.inliers.empty(); }
  bool Linearize(const State& state, Linearization* ne) const {
    return esdslam::Linearize(k_, problem_, layout_, options_, state, ne);
  }
  double CostOf(const Linearization& ne) const { return ne.cost; }
  bool Solve(const Linearization& ne, double lambda, Step* step, double* model_decrease) const {
    return SolveDamped(ne, layout_, problem_, lambda, step, model_decrease);
  }
  bool StepIsTiny(const State& state, const Step& step, double tolerance) const {
    return esdslam::StepIsTiny(state, layout_, step, tolerance);
  }
  State Apply(const State& state, const Step& step) const { return esdslam::Apply(state, layout_, step); }
  double Cost(const State& state) const { return esdslam::Cost(k_, problem_, layout_, options_, state); }

 private:
  const StereoIntrinsics& k_;
  const BaProblem& problem_;
  const SchurLmOptions& options_;
  Layout layout_;
};

}  // namespace

SchurLmSummary SolveSchurLm(const StereoIntrinsics& k, const BaProblem& problem, const SchurLmOptions& options,
                            const std::atomic<bool>* stop, BaState* state) {
  const SchurBaProblem window(k, problem, options);
  if (window.empty()) return {};
  LmControl control;
  control.max_iterations = options.max_iterations;
  control.function_tolerance = options.function_tolerance;
  control.parameter_tolerance = options.parameter_tolerance;
  const LmOutcome outcome = MinimizeLm(window, control, stop, state);
  SchurLmSummary summary;
  summary.initial_cost = outcome.initial_cost;
  summary.final_cost = outcome.final_cost;
  summary.iterations = outcome.iterations;
  summary.stopped = outcome.stopped;
  return summary;
}

}  // namespace esdslam
