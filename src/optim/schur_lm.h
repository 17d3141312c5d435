#pragma once
// Levenberg-Marquardt for bundle adjustment with the points eliminated first (Schur complement)
// and the reduced camera system solved densely. Every block has a fixed size (6-D pose tangent,
// 3-D point, 2- or 3-row residual), so all block algebra uses Eigen fixed-size matrices; the
// reduced system is 6F x 6F for F free keyframes, meant for local windows (tens of keyframes).
//
// Steps follow Ceres' Levenberg-Marquardt strategy (damping lambda * clamp(diag(H)), initial
// lambda 1e-4, Nielsen's update on accepted steps, doubling on rejected ones; an iteration is one
// linear solve, accepted or not), so results match the Ceres path in quality. The robust loss is
// Huber, applied by iteratively reweighted least squares (weight delta / |r| beyond delta), as
// g2o does for ORB-SLAM2.

#include <array>
#include <atomic>
#include <cmath>
#include <vector>

#include "optim/bundle_adjustment.h"
#include "optim/reprojection_cost.h"

namespace esdslam {

// Estimates being optimised: pose blocks in reprojection_cost.h's layout (cam_from_world),
// world points (m).
struct BaState {
  std::vector<std::array<double, kPoseBlockSize>> poses;
  std::vector<Vec3> points;
};

// An observation as the residuals see it (whitening by sqrt(information)).
inline ReprojectionMeasurement BaMeasurement(const BaObservation& o) {
  return {o.pixel, o.right_u, std::sqrt(o.information)};
}

struct SchurLmOptions {
  int max_iterations = 10;            // linear solves, accepted or rejected
  bool robust = false;                // Huber with the two deltas below (sqrt of chi2, whitened px)
  double huber_delta_mono = 1;
  double huber_delta_stereo = 1;
  double function_tolerance = 1e-6;   // converged when |cost change| / cost falls below this
  double parameter_tolerance = 1e-8;  // ... or |step| <= tol * (|x| + tol)
};

struct SchurLmSummary {
  double initial_cost = 0;  // 0.5 * sum of (robustified) chi2, as Ceres reports cost
  double final_cost = 0;
  int iterations = 0;       // linear solves done
  bool stopped = false;     // ended early by the stop flag
};

// Minimises over the observations not flagged outlier in `problem` (indices already validated);
// keyframes and points flagged fixed stay bitwise unchanged, as do blocks no inlier touches.
// Every inlier must be in front of its camera at the start (callers flag the others); a step
// that puts one behind is rejected. `stop` (may be null) ends the solve between iterations,
// keeping the best estimate so far.
SchurLmSummary SolveSchurLm(const StereoIntrinsics& k, const BaProblem& problem, const SchurLmOptions& options,
                            const std::atomic<bool>* stop, BaState* state);

}  // namespace esdslam
