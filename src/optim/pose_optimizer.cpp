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

// The prior's residual (pose_optimizer.h) with its Jacobian w.r.t. the left tangent delta:
// rho' = Exp(dphi) rho + drho and phi' ~ dphi + phi, so d(rho, phi)/d(drho, dphi) = [I, -[rho]x; 0, I]
// (the rotation part to first order, exact at the prior).
class PosePriorCost final : public ceres::SizedCostFunction<6, kPoseBlockSize> {
 public:
  explicit PosePriorCost(const PosePrior& prior) : prior_(prior) {}
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const Rigid3 pose = PoseFromBlock(parameters[0]);
    const Quat dq = pose.rotation() * prior_.cam_from_world.rotation().conjugate();
    const Vec3 rho = pose.translation() - dq * prior_.cam_from_world.translation();
    const Vec3 phi = LogSO3(dq.toRotationMatrix());
    const double wt = 1.0 / prior_.sigma_translation_m, wr = 1.0 / prior_.sigma_rotation_rad;
    Eigen::Map<Eigen::Matrix<double, 6, 1>> r(residuals);
    r << wt * rho, wr * phi;
    if (jacobians != nullptr && jacobians[0] != nullptr) {
      Eigen::Map<Eigen::Matrix<double, 6, kPoseBlockSize, Eigen::RowMajor>> j(jacobians[0]);
      j.setZero();
      j.block<3, 3>(0, 0) = wt * Mat3::Identity();
      j.block<3, 3>(0, 3) << 0, wt * rho.z(), -wt * rho.y(), -wt * rho.z(), 0, wt * rho.x(), wt * rho.y(), -wt * rho.x(), 0;
      j.block<3, 3>(3, 3) = wr * Mat3::Identity();
    }
    return true;
  }

 private:
  PosePrior prior_;
};

struct RoundContext {
  const std::vector<PoseObservation>* observations;
  const std::vector<std::unique_ptr<ceres::CostFunction>>* costs;
  ceres::CostFunction* prior;  // null = none
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
  if (context.prior != nullptr) problem.AddResidualBlock(context.prior, nullptr, block);
  ceres::Solver::Summary summary;
  ceres::Solve(SmallProblemOptions(iterations), &problem, &summary);
  if (summary.IsSolutionUsable()) std::copy(block, block + kPoseBlockSize, pose_block);
}

}  // namespace

int OptimizePose(const PinholeCamera& camera, double bf, const PoseOptimizerOptions& options,
                 std::vector<PoseObservation>* observations, Rigid3* cam_from_world, const PosePrior* prior) {
  options.Check();
  if (prior != nullptr && !(prior->sigma_translation_m > 0 && prior->sigma_rotation_rad > 0))
    throw Error("OptimizePose: the prior's sigmas must be positive");
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
  std::unique_ptr<ceres::CostFunction> prior_cost;
  if (prior != nullptr) prior_cost = std::make_unique<PosePriorCost>(*prior);
  const RoundContext context{observations, &costs, prior_cost.get(), &huber_mono, &huber_stereo, &manifold};

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
