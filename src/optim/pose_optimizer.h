#pragma once
// Motion-only bundle adjustment (ORB-SLAM2's Optimizer::PoseOptimization): Levenberg-Marquardt
// on the 6-D pose tangent (optim/levenberg_marquardt.h), 6x6 normal equations.

#include <vector>

#include "camera/pinhole_camera.h"
#include "common/geometry.h"

namespace esdslam {

struct PoseObservation {
  Vec3 point_world;
  Vec2 pixel;              // undistorted keypoint (u, v), px
  double right_u = -1;     // virtual right-camera u = u - bf / depth; < 0: no depth -> 2-D residual
  double information = 1;  // inverse sigma^2 of the keypoint's pyramid level
  bool outlier = false;    // in/out: set by the optimiser
};

struct PoseOptimizerOptions {
  int rounds = 4;                 // optimise / re-classify cycles
  int iterations_per_round = 10;  // Levenberg-Marquardt iterations per round
  double chi2_mono = 5.991;       // 95% chi2, 2 DoF
  double chi2_stereo = 7.815;     // 95% chi2, 3 DoF
  // Huber loss in the first half of the rounds (at least one), plain least squares after
  // (ORB-SLAM2: 2 of 4 rounds robust).
  bool robust_first_rounds = true;
  void Check() const;
};

// A Gaussian prior on the pose (the motion model's prediction): residual
// (rho / sigma_translation_m, phi / sigma_rotation_rad) with (rho, phi) = cam_from_world minus
// the prior in the pose tangent (optim/reprojection_cost.h: phi the rotation vector of
// R R_prior^-1, rho = t - R R_prior^-1 t_prior, the offset of the prior camera's origin in the
// camera frame). Added, without a robust loss, to every round; it never makes an observation an
// outlier. It pins the directions the observations leave weak (few inliers, all on one side of
// the image) and barely moves the ones they constrain.
// With a non-zero `sqrt_information` S (6x6, in the same (rho, phi) tangent) the residual is
// S (rho, phi) instead, so its cost is (rho, phi)^T S^T S (rho, phi) / 2: a prior that holds some
// directions firmly and leaves others free (the depth alignment's, tracking/depth_alignment.h).
struct PosePrior {
  Rigid3 cam_from_world;
  double sigma_translation_m = 0.01;  // per axis
  double sigma_rotation_rad = 0.01;   // per axis
  Eigen::Matrix<double, 6, 6> sqrt_information = Eigen::Matrix<double, 6, 6>::Zero();  // zero: the sigmas
};

// Optimises cam_from_world in place (initial value = input). Every observation starts as an
// inlier (input outlier flags are ignored) unless its point is behind the camera. Each round
// optimises over the current inliers (Huber loss with delta = sqrt(chi2 threshold) in the robust
// rounds), then re-classifies every observation as inlier / outlier by its chi2 at the new pose;
// points behind the camera are outliers. Each round starts from the previous round's pose.
// Returns the number of inliers. With fewer than 3 inliers no round runs (pose unchanged).
// Throws Error when bf <= 0 while some observation has a right_u, or on invalid options.
// `prior` (null = none, sigmas must be positive) is added as described above.
int OptimizePose(const PinholeCamera& camera, double bf, const PoseOptimizerOptions& options,
                 std::vector<PoseObservation>* observations, Rigid3* cam_from_world,
                 const PosePrior* prior = nullptr);

}  // namespace esdslam
