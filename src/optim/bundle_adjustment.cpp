#include "optim/bundle_adjustment.h"

#include <array>
#include <cmath>
#include <memory>

#include <ceres/ceres.h>
#include <fmt/format.h>

#include "common/error.h"
#include "optim/reprojection_cost.h"
#include "optim/schur_lm.h"

namespace esdslam {

void BundleAdjustmentOptions::Check() const {
  if (iterations_first <= 0 || iterations_second < 0)
    throw Error("BundleAdjustmentOptions: iterations_first must be > 0 and iterations_second >= 0");
  if (!(chi2_mono > 0) || !(chi2_stereo > 0)) throw Error("BundleAdjustmentOptions: chi2 thresholds must be > 0");
  if (num_threads <= 0) throw Error("BundleAdjustmentOptions: num_threads must be positive");
  if (max_dense_keyframes < 0 || max_dense_keyframes > 500)
    throw Error("BundleAdjustmentOptions: max_dense_keyframes must be in [0, 500]");
}

namespace {

class StopCallback final : public ceres::IterationCallback {
 public:
  explicit StopCallback(const std::atomic<bool>* stop) : stop_(stop) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& /*summary*/) override {
    if (stop_ == nullptr || !stop_->load()) return ceres::SOLVER_CONTINUE;
    stopped_ = true;
    return ceres::SOLVER_TERMINATE_SUCCESSFULLY;  // keeps the best iterate
  }
  bool stopped() const { return stopped_; }

 private:
  const std::atomic<bool>* stop_;
  bool stopped_ = false;
};

void Validate(double bf, const BaProblem& problem) {
  const int num_keyframes = static_cast<int>(problem.keyframes.size());
  const int num_points = static_cast<int>(problem.points.size());
  for (size_t i = 0; i < problem.observations.size(); ++i) {
    const BaObservation& o = problem.observations[i];
    if (o.keyframe < 0 || o.keyframe >= num_keyframes || o.point < 0 || o.point >= num_points)
      throw Error(fmt::format("BundleAdjust: observation {} refers to keyframe {} / point {} out of range", i,
                              o.keyframe, o.point));
    if (!(o.information > 0)) throw Error(fmt::format("BundleAdjust: observation {} has information <= 0", i));
    if (o.right_u >= 0 && !(bf > 0)) throw Error("BundleAdjust: observations with depth need bf > 0");
  }
}

BaState StateOf(const BaProblem& problem) {
  BaState state;
  state.poses.resize(problem.keyframes.size());
  for (size_t i = 0; i < problem.keyframes.size(); ++i)
    PoseToBlock(problem.keyframes[i].cam_from_world, state.poses[i].data());
  state.points.reserve(problem.points.size());
  for (const BaPoint& point : problem.points) state.points.push_back(point.position_world);
  return state;
}

// Flags observations whose chi2 exceeds the threshold or whose point is behind the camera
// (or, with check_chi2 false, only the latter). Returns the number of outliers.
int FlagOutliers(const StereoIntrinsics& k, const BundleAdjustmentOptions& options, const BaState& state,
                 bool check_chi2, BaProblem* problem) {
  int outliers = 0;
  for (BaObservation& o : problem->observations) {
    const ReprojectionMeasurement m = BaMeasurement(o);
    bool in_front = false;
    const double chi2 = ReprojectionChi2(k, m, PoseFromBlock(state.poses[o.keyframe].data()), state.points[o.point],
                                         &in_front);
    o.outlier = !in_front || (check_chi2 && chi2 > (m.stereo() ? options.chi2_stereo : options.chi2_mono));
    if (o.outlier) ++outliers;
  }
  return outliers;
}

struct PhaseInput {
  const StereoIntrinsics* k;
  const std::atomic<bool>* stop;
  const BaProblem* problem;
  const BundleAdjustmentOptions* options;
  ceres::Manifold* manifold;
  StopCallback* callback;
};

// Adds the inlier residuals (robust: Huber with delta = sqrt(chi2 threshold)) and the blocks
// they touch; returns the Schur elimination ordering (points first) or null.
std::shared_ptr<ceres::ParameterBlockOrdering> BuildProblem(const PhaseInput& in, bool robust,
                                                            const std::vector<ceres::LossFunction*>& huber,
                                                            const std::vector<std::unique_ptr<ceres::CostFunction>>& costs,
                                                            BaState* state, ceres::Problem* ceres_problem) {
  const BaProblem& problem = *in.problem;
  auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
  int free_points = 0, free_poses = 0;
  for (size_t i = 0; i < problem.observations.size(); ++i) {
    const BaObservation& o = problem.observations[i];
    if (o.outlier) continue;
    double* pose = state->poses[o.keyframe].data();
    double* point = state->points[o.point].data();
    if (!ceres_problem->HasParameterBlock(pose)) {
      ceres_problem->AddParameterBlock(pose, kPoseBlockSize, in.manifold);
      ordering->AddElementToGroup(pose, 1);
      if (problem.keyframes[o.keyframe].fixed) ceres_problem->SetParameterBlockConstant(pose);
      else ++free_poses;
    }
    if (!ceres_problem->HasParameterBlock(point)) {
      ceres_problem->AddParameterBlock(point, 3);
      ordering->AddElementToGroup(point, 0);
      if (problem.points[o.point].fixed) ceres_problem->SetParameterBlockConstant(point);
      else ++free_points;
    }
    ceres::LossFunction* loss = robust ? huber[o.right_u >= 0 ? 1 : 0] : nullptr;
    ceres_problem->AddResidualBlock(costs[i].get(), loss, pose, point);
  }
  if (free_points == 0 || free_poses == 0) return nullptr;
  return ordering;
}

struct PhaseResult {
  double initial_cost = 0;
  double final_cost = 0;
  bool usable = true;    // the estimate is a valid iterate
  bool stopped = false;  // ended by the stop flag
};

// One Levenberg-Marquardt phase over the inliers with Ceres (large windows).
PhaseResult SolvePhaseWithCeres(const PhaseInput& in, bool robust, int iterations, BaState* state) {
  ceres::HuberLoss huber_mono(std::sqrt(in.options->chi2_mono)), huber_stereo(std::sqrt(in.options->chi2_stereo));
  ceres::Problem::Options problem_options;
  problem_options.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem ceres_problem(problem_options);
  std::vector<std::unique_ptr<ceres::CostFunction>> costs;
  costs.reserve(in.problem->observations.size());
  for (const BaObservation& o : in.problem->observations) costs.emplace_back(NewPosePointCost(*in.k, BaMeasurement(o)));
  auto ordering = BuildProblem(in, robust, {&huber_mono, &huber_stereo}, costs, state, &ceres_problem);

  ceres::Solver::Options solver_options;
  solver_options.max_num_iterations = iterations;
  solver_options.num_threads = in.options->num_threads;
  solver_options.logging_type = ceres::SILENT;
  solver_options.callbacks.push_back(in.callback);
  if (ordering != nullptr && ceres::IsSparseLinearAlgebraLibraryTypeAvailable(ceres::SUITE_SPARSE)) {
    solver_options.linear_solver_type = ceres::SPARSE_SCHUR;
    solver_options.linear_solver_ordering = ordering;
  } else if (ordering != nullptr) {
    solver_options.linear_solver_type = ceres::DENSE_SCHUR;
    solver_options.linear_solver_ordering = ordering;
  } else {
    solver_options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
    if (!ceres::IsSparseLinearAlgebraLibraryTypeAvailable(ceres::SUITE_SPARSE))
      solver_options.linear_solver_type = ceres::DENSE_QR;
  }
  PhaseResult result;
  if (ceres_problem.NumResidualBlocks() == 0) return result;  // nothing to optimise
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &ceres_problem, &summary);
  result.initial_cost = summary.initial_cost;
  result.final_cost = summary.final_cost;
  result.usable = summary.IsSolutionUsable();
  result.stopped = in.callback->stopped();
  return result;
}

int FreeKeyframes(const BaProblem& problem) {
  return static_cast<int>(std::count_if(problem.keyframes.begin(), problem.keyframes.end(),
                                        [](const BaKeyframe& keyframe) { return !keyframe.fixed; }));
}

// One Levenberg-Marquardt phase over the inliers.
PhaseResult SolvePhase(const PhaseInput& in, bool robust, int iterations, BaState* state) {
  if (FreeKeyframes(*in.problem) > in.options->max_dense_keyframes) return SolvePhaseWithCeres(in, robust, iterations, state);
  SchurLmOptions lm;
  lm.max_iterations = iterations;
  lm.robust = robust;
  lm.huber_delta_mono = std::sqrt(in.options->chi2_mono);
  lm.huber_delta_stereo = std::sqrt(in.options->chi2_stereo);
  const SchurLmSummary summary = SolveSchurLm(*in.k, *in.problem, lm, in.stop, state);
  PhaseResult result;
  result.initial_cost = summary.initial_cost;
  result.final_cost = summary.final_cost;
  result.stopped = summary.stopped;
  return result;
}

void WriteBack(const BaState& state, BaProblem* problem) {
  for (size_t i = 0; i < problem->keyframes.size(); ++i)
    if (!problem->keyframes[i].fixed) problem->keyframes[i].cam_from_world = PoseFromBlock(state.poses[i].data());
  for (size_t i = 0; i < problem->points.size(); ++i)
    if (!problem->points[i].fixed) problem->points[i].position_world = state.points[i];
}

}  // namespace

BaSummary BundleAdjust(const PinholeCamera& camera, double bf, const BundleAdjustmentOptions& options,
                       BaProblem* problem, const std::atomic<bool>* stop) {
  options.Check();
  if (problem == nullptr) throw Error("BundleAdjust: null problem");
  Validate(bf, *problem);
  BaSummary result;
  for (BaObservation& o : problem->observations) o.outlier = false;
  if (stop != nullptr && stop->load()) {
    result.aborted = true;
    return result;
  }
  const StereoIntrinsics k(camera, bf);
  BaState state = StateOf(*problem);
  PoseManifold manifold;
  StopCallback callback(stop);
  const PhaseInput in{&k, stop, problem, &options, &manifold, &callback};

  // Residuals cannot be evaluated behind the camera: such observations never enter.
  FlagOutliers(k, options, state, /*check_chi2=*/false, problem);
  const PhaseResult first = SolvePhase(in, /*robust=*/true, options.iterations_first, &state);
  result.initial_cost = first.initial_cost;
  result.final_cost = first.final_cost;
  result.aborted = first.stopped;
  if (!result.aborted && options.iterations_second > 0) {
    FlagOutliers(k, options, state, /*check_chi2=*/true, problem);
    const PhaseResult second = SolvePhase(in, /*robust=*/false, options.iterations_second, &state);
    if (second.usable) result.final_cost = second.final_cost;
    result.aborted = second.stopped;
  }
  result.outliers = FlagOutliers(k, options, state, /*check_chi2=*/true, problem);
  WriteBack(state, problem);
  return result;
}

}  // namespace esdslam
