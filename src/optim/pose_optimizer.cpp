#include "optim/pose_optimizer.h"

#include <array>
#include <cmath>
#include <limits>

#include <Eigen/Cholesky>

#include "common/error.h"
#include "optim/levenberg_marquardt.h"
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

// The prior's residual (pose_optimizer.h) and its Jacobian w.r.t. the left tangent delta:
// rho' = Exp(dphi) rho + drho and phi' ~ dphi + phi, so d(rho, phi)/d(drho, dphi) = [I, -[rho]x; 0, I]
// (the rotation part to first order, exact at the prior).
Vec6 PriorResidual(const PosePrior& prior, const double* pose_block, Mat6* jacobian) {
  const Rigid3 pose = PoseFromBlock(pose_block);
  const Quat dq = pose.rotation() * prior.cam_from_world.rotation().conjugate();
  const Vec3 rho = pose.translation() - dq * prior.cam_from_world.translation();
  const Vec3 phi = LogSO3(dq.toRotationMatrix());
  if (!prior.sqrt_information.isZero()) {
    Vec6 difference;
    difference << rho, phi;
    if (jacobian != nullptr) {
      Mat6 tangent = Mat6::Identity();
      tangent.block<3, 3>(0, 3) = -Skew(rho);
      *jacobian = prior.sqrt_information * tangent;
    }
    return prior.sqrt_information * difference;
  }
  const double wt = 1.0 / prior.sigma_translation_m, wr = 1.0 / prior.sigma_rotation_rad;
  Vec6 r;
  r << wt * rho, wr * phi;
  if (jacobian != nullptr) {
    jacobian->setZero();
    jacobian->block<3, 3>(0, 0) = wt * Mat3::Identity();
    jacobian->block<3, 3>(0, 3) = -wt * Skew(rho);
    jacobian->block<3, 3>(3, 3) = wr * Mat3::Identity();
  }
  return r;
}

// One round's least-squares problem over the current inliers, as MinimizeLm's Problem
// (levenberg_marquardt.h): the pose block is the state, the 6-D tangent the step.
class PoseRound {
 public:
  using State = std::array<double, kPoseBlockSize>;
  using Step = Vec6;
  struct Linearization {
    double cost = 0;
    Mat6 h = Mat6::Zero();  // J^T W J
    Vec6 b = Vec6::Zero();  // -J^T W r
  };

  PoseRound(const StereoIntrinsics& k, const std::vector<PoseObservation>& observations,
            const std::vector<ReprojectionMeasurement>& measurements, const PosePrior* prior, double delta_mono,
            double delta_stereo)
      : k_(k), observations_(observations), measurements_(measurements), prior_(prior),
        delta_mono_(delta_mono), delta_stereo_(delta_stereo) {}

  bool Linearize(const State& pose, Linearization* out) const { return Evaluate(pose, out); }
  double CostOf(const Linearization& linearization) const { return linearization.cost; }
  bool Solve(const Linearization& linearization, double lambda, Step* step, double* model_decrease) const {
    Mat6 damped = linearization.h;
    const Vec6 damping = LmDamping(linearization.h, lambda);
    damped.diagonal() += damping;
    const Eigen::LDLT<Mat6> ldlt(damped);
    if (ldlt.info() != Eigen::Success) return false;
    *step = ldlt.solve(linearization.b);
    // (H + D) dx = b: the quadratic model falls by (dx.b + dx.D.dx) / 2.
    *model_decrease = 0.5 * step->dot(linearization.b + damping.cwiseProduct(*step));
    return step->allFinite();
  }
  bool StepIsTiny(const State& pose, const Step& step, double tolerance) const {
    const double x_norm = Eigen::Map<const Eigen::Matrix<double, kPoseBlockSize, 1>>(pose.data()).norm();
    return step.norm() <= tolerance * (x_norm + tolerance);
  }
  State Apply(const State& pose, const Step& step) const {
    State next;
    PoseManifold().Plus(pose.data(), step.data(), next.data());
    return next;
  }
  double Cost(const State& pose) const { return Evaluate(pose, nullptr); }

 private:
  // Cost at `pose` (+inf if an inlier is behind the camera); fills *out if not null.
  double Evaluate(const State& pose, Linearization* out) const;
  template <int R>
  bool AddTerm(const ReprojectionMeasurement& m, const Vec3& point_world, const State& pose, double* cost,
               Linearization* out) const;

  const StereoIntrinsics& k_;
  const std::vector<PoseObservation>& observations_;
  const std::vector<ReprojectionMeasurement>& measurements_;
  const PosePrior* prior_;
  double delta_mono_, delta_stereo_;
};

template <int R>
bool PoseRound::AddTerm(const ReprojectionMeasurement& m, const Vec3& point_world, const State& pose, double* cost,
                        Linearization* out) const {
  Eigen::Matrix<double, R, 1> r;
  Eigen::Matrix<double, R, 6> j;
  if (!EvaluateReprojection<R>(k_, m, pose.data(), point_world, &r, out != nullptr ? &j : nullptr, nullptr))
    return false;
  double weight = 1;
  *cost += 0.5 * HuberRho(r.squaredNorm(), R == 3 ? delta_stereo_ : delta_mono_, &weight);
  if (out != nullptr) {
    out->h.noalias() += weight * j.transpose() * j;
    out->b.noalias() -= weight * j.transpose() * r;
  }
  return true;
}

double PoseRound::Evaluate(const State& pose, Linearization* out) const {
  if (out != nullptr) *out = Linearization{};
  double cost = 0;
  for (size_t i = 0; i < observations_.size(); ++i) {
    if (observations_[i].outlier) continue;
    const ReprojectionMeasurement& m = measurements_[i];
    const bool ok = m.stereo() ? AddTerm<3>(m, observations_[i].point_world, pose, &cost, out)
                               : AddTerm<2>(m, observations_[i].point_world, pose, &cost, out);
    if (!ok) return std::numeric_limits<double>::infinity();
  }
  if (prior_ != nullptr) {
    Mat6 j;
    const Vec6 r = PriorResidual(*prior_, pose.data(), out != nullptr ? &j : nullptr);
    cost += 0.5 * r.squaredNorm();
    if (out != nullptr) {
      out->h.noalias() += j.transpose() * j;
      out->b.noalias() -= j.transpose() * r;
    }
  }
  if (out != nullptr) out->cost = cost;
  return cost;
}

// Levenberg-Marquardt over the current inliers; updates pose_block when the start is evaluable.
void SolveRound(const PoseRound& round, int iterations, std::array<double, kPoseBlockSize>* pose_block) {
  LmControl control;
  control.max_iterations = iterations;
  std::array<double, kPoseBlockSize> pose = *pose_block;
  if (MinimizeLm(round, control, nullptr, &pose).evaluable) *pose_block = pose;
}

}  // namespace

int OptimizePose(const PinholeCamera& camera, double bf, const PoseOptimizerOptions& options,
                 std::vector<PoseObservation>* observations, Rigid3* cam_from_world, const PosePrior* prior) {
  options.Check();
  if (prior != nullptr && prior->sqrt_information.isZero() && !(prior->sigma_translation_m > 0 && prior->sigma_rotation_rad > 0))
    throw Error("OptimizePose: the prior's sigmas must be positive");
  if (prior != nullptr && !prior->sqrt_information.allFinite()) throw Error("OptimizePose: the prior's information is not finite");
  if (observations == nullptr || cam_from_world == nullptr) throw Error("OptimizePose: null output");
  const StereoIntrinsics k(camera, bf);
  std::vector<ReprojectionMeasurement> measurements;
  measurements.reserve(observations->size());
  for (const PoseObservation& observation : *observations) {
    if (observation.right_u >= 0 && !(bf > 0)) throw Error("OptimizePose: observations with depth need bf > 0");
    measurements.push_back(MeasurementOf(observation));
  }
  const double plain = std::numeric_limits<double>::infinity();
  const PoseRound robust_round(k, *observations, measurements, prior, std::sqrt(options.chi2_mono),
                               std::sqrt(options.chi2_stereo));
  const PoseRound plain_round(k, *observations, measurements, prior, plain, plain);

  std::array<double, kPoseBlockSize> pose_block;
  PoseToBlock(*cam_from_world, pose_block.data());
  int inliers = ResetFlags(*cam_from_world, observations);
  const int robust_rounds = options.rounds > 1 ? std::max(1, options.rounds / 2) : 1;
  int round = 0;
  for (; round < options.rounds && inliers >= kMinInliers; ++round) {
    const bool robust = options.robust_first_rounds && round < robust_rounds;
    SolveRound(robust ? robust_round : plain_round, options.iterations_per_round, &pose_block);
    inliers = Classify(k, options, PoseFromBlock(pose_block.data()), observations);
  }
  if (round > 0) *cam_from_world = PoseFromBlock(pose_block.data());
  return inliers;
}

}  // namespace esdslam
