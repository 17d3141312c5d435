#pragma once
// Depth alignment of a frame to the previous one (issue 13: tracking when the static area is
// small): point-to-plane ICP of the frame's static depth against the previous frame's static
// depth, with projective data association, from an initial pose (the feature-tracked one).
//
// Samples: every `sample_stride_px`-th pixel of the frame with a depth reading in
// [min_depth_m, max_depth_m] and off its dynamic mask, back-projected into its camera frame
// (distortion removed). Each iteration moves a sample into the reference camera (the previous
// frame at its tracked pose), projects it (distortion applied, nearest pixel) and, where the
// reference has a static reading d whose 4-neighbours 2 px away lie on one surface, takes that
// reading's point q and the surface normal n there:
//   r = n . (p_ref - q),  sigma^2 = sigma(z)^2 + sigma(d)^2,  sigma(z) = depth_noise_at_1m * z^2,
// Huber-weighted at 1 sigma, gated at gate_sigmas. Gauss-Newton on cam_from_world with a left
// perturbation (rho, phi): T' = Exp(phi) T, t' = Exp(phi) t + rho (the order of PosePrior).
//
// The result is the aligned cam_from_world with the information matrix of the last
// linearisation (J^T W J over the accepted samples): what the depth says about the pose, and
// how firmly in each direction (a single wall leaves its in-plane directions free: zero
// eigenvalues). Used as a Gaussian prior of the feature pose optimisation (optim/pose_optimizer.h).

#include <optional>

#include <opencv2/core.hpp>

#include "camera/pinhole_camera.h"
#include "common/geometry.h"

namespace esdslam {

struct DepthAlignmentOptions {
  int sample_stride_px = 8;          // px between samples in u and v
  double min_depth_m = 0.3;          // m
  double max_depth_m = 4.0;          // m: Xtion / Kinect v1 noise grows with z^2
  double depth_noise_at_1m = 0.0015; // m: sigma(z) = this * z^2 (Khoshelham and Elberink 2012)
  double gate_sigmas = 4.0;          // residuals beyond this many sigmas are not associated
  double same_surface_ratio = 0.05;  // neighbours for the normal within this fraction of d
  int iterations = 10;
  int min_samples = 300;             // fewer associated samples: no result
  void Check() const;
};

struct DepthAlignment {
  Rigid3 cam_from_world;
  Eigen::Matrix<double, 6, 6> information = Eigen::Matrix<double, 6, 6>::Zero();  // in the (rho, phi) left tangent at cam_from_world
  int samples = 0;                  // associated samples of the last iteration
};

// The alignment for one camera: the sample grid's undistorted rays are computed once.
class DepthAligner {
 public:
  DepthAligner(const PinholeCamera& camera, const DepthAlignmentOptions& options = {});
  // depth_m / reference_depth_m: CV_32F metres (0 = invalid), the camera's raw image size; masks
  // CV_8U (nonzero = dynamic) or empty. Returns nothing when too few samples associate.
  std::optional<DepthAlignment> Align(const cv::Mat& depth_m, const cv::Mat& dynamic_mask, const cv::Mat& reference_depth_m,
                                      const cv::Mat& reference_dynamic_mask, const Rigid3& reference_cam_from_world,
                                      const Rigid3& initial_cam_from_world) const;

 private:
  PinholeCamera camera_;
  DepthAlignmentOptions options_;
  cv::Mat ray_x_, ray_y_;  // CV_64F per grid sample: undistorted (x / z, y / z)
};

// One alignment with a DepthAligner made for it (see there).
std::optional<DepthAlignment> AlignDepth(const PinholeCamera& camera, const cv::Mat& depth_m, const cv::Mat& dynamic_mask,
                                         const cv::Mat& reference_depth_m, const cv::Mat& reference_dynamic_mask,
                                         const Rigid3& reference_cam_from_world, const Rigid3& initial_cam_from_world,
                                         const DepthAlignmentOptions& options = {});

}  // namespace esdslam
