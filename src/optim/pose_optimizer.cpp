#include "optim/pose_optimizer.h"
#include "optim/small_problem_options.h"

#include <cmath>
#include <memory>

#include <ceres/ceres.h>

#include "common/error.h"
#include "optim/reprojection_cost.h"

namespace esdslam {

void PoseOptimizerOptions::Check() const {
  if (rounds <= 0) throw Error("PoseOptimizerOptions: rounds must be positive");
  if (iterations_per_round <= 0) throw Error("PoseOptimizerOptions: iterations_per_round must be positive");
  if (!(chi2_mono > 0) || !(chi2_stereo > 0)) throw Error("PoseOptimizerOptions: chi2 thresholds must be > 0");
}

namespace {

constexpr int kMinInliers = 3;

ReprojectionMeasurement MeasurementOf(const PoseObservation& observation) {
  if (!(observation.information > 0)) throw Error("PoseObservation: information must be positive");
  return {observation.pixel, observation.right_u, std::sqrt(observation.information)};
}

// Flags every observation by its chi2 at the pose; returns the number of inliers.
int Classify(const StereoIntrinsics& k, const PoseOptimizerOptions& options, const Rigid3& cam_from_world,
             std::vector<PoseObservation>* observations) {
  int inliers = 0;
  for (PoseObservation& observation : *observations) {
    const ReprojectionMeasurement m = MeasurementOf(observation);
    bool in_front = false;
    const double chi2 = ReprojectionChi2(k, m, cam_from_world, observation.point_world, &in_front);
    observation.outlier = !in_front || chi2 > (m.stereo() ? options.chi2_stereo : options.chi2_mono);
    if (!observation.outlier) ++inliers;
  }
  return inliers;
}

// Marks only the points behind the camera as outliers; returns the number of inliers.
int ResetFlags(const Rigid3& cam_from_world, std::vector<PoseObservation>* observations) {
  int inliers = 0;
  for (PoseObservation& observation : *observations) {
    observation.outlier = !((cam_from_world * observation.point_world).z() > kMinPositiveDepth);
    if (!observation.outlier) ++inliers;
  }
  return inliers;
}

struct RoundContext {
  const std::vector<PoseObservation>* observations;
  const std::vector<std::unique_ptr<ceres::CostFunction>>* costs;
  ceres::LossFunction* huber_mono;
  ceres::LossFunction* huber_stereo;
  ceres::Manifold* manifold;
};

// Levenberg-Marquardt over the current inliers; updates pose_block when the solution is usable.
void SolveRound(const RoundContext& context, bool robust, int iterations, double* pose_block) {
  ceres::Problem::Options problem_options;
  problem_options.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  double block[kPoseBlockSize];
  std::copy(pose_block, pose_block + kPoseBlockSize, block);
  problem.AddParameterBlock(block, kPoseBlockSize, context.manifold);
  const auto& observations = *context.observations;
  for (size_t i = 0; i < observations.size(); ++i) {
    if (observations[i].outlier) continue;
    ceres::LossFunction* loss = nullptr;
    if (robust) loss = observations[i].right_u >= 0 ? context.huber_stereo : context.huber_mono;
    problem.AddResidualBlock((*context.costs)[i].get(), loss, block);
  }
  ceres::Solver::Summary summary;
  ceres::Solve(SmallProblemOptions(iterations), &problem, &summary);
  if (summary.IsSolutionUsable()) std::copy(block, block + kPoseBlockSize, pose_block);
}

}  // namespace

int OptimizePose(const PinholeCamera& camera, double bf, const PoseOptimizerOptions& options,
                 std::vector<PoseObservation>* observations, Rigid3* cam_from_world) {
  options.Check();
  if (observations == nullptr || cam_from_world == nullptr) throw Error("OptimizePose: null output");
  const StereoIntrinsics k(camera, bf);
  std::vector<std::unique_ptr<ceres::CostFunction>> costs;
  costs.reserve(observations->size());
  for (const PoseObservation& observation : *observations) {
    if (observation.right_u >= 0 && !(bf > 0)) throw Error("OptimizePose: observations with depth need bf > 0");
    costs.emplace_back(NewPoseOnlyCost(k, MeasurementOf(observation), observation.point_world));
  }
  ceres::HuberLoss huber_mono(std::sqrt(options.chi2_mono)), huber_stereo(std::sqrt(options.chi2_stereo));
  PoseManifold manifold;
  const RoundContext context{observations, &costs, &huber_mono, &huber_stereo, &manifold};

  double pose_block[kPoseBlockSize];
  PoseToBlock(*cam_from_world, pose_block);
  int inliers = ResetFlags(*cam_from_world, observations);
  const int robust_rounds = options.rounds > 1 ? std::max(1, options.rounds / 2) : 1;
  int round = 0;
  for (; round < options.rounds && inliers >= kMinInliers; ++round) {
    const bool robust = options.robust_first_rounds && round < robust_rounds;
    SolveRound(context, robust, options.iterations_per_round, pose_block);
    inliers = Classify(k, options, PoseFromBlock(pose_block), observations);
  }
  if (round > 0) *cam_from_world = PoseFromBlock(pose_block);
  return inliers;
}

}  // namespace esdslam
