#pragma once
// Camera pose from 3-D/2-D matches for relocalization: RANSAC over minimal P3P solutions
// (OpenCV's AP3P on 4-point samples drawn with our seeded RNG), then iterative (Levenberg-
// Marquardt) refinement on the inliers, re-selected until stable. Pixels are undistorted and
// the intrinsics known.

#include <cstdint>
#include <vector>

#include "camera/pinhole_camera.h"
#include "common/geometry.h"

namespace esdslam {

struct PnpRansacOptions {
  // Inlier when the reprojection error < max_error_px * pixel_scale (chi2(2, 0.95) = 5.991 ->
  // 2.45 px, ORB-SLAM2's PnPsolver threshold).
  double max_error_px = 2.45;
  double confidence = 0.99;
  int max_iterations = 300;
  int min_inliers = 15;
  int refine_rounds = 5;
  std::uint32_t seed = 1;

  void Check() const;
};

struct PnpRansacResult {
  bool success = false;  // num_inliers >= min_inliers
  Rigid3 cam_from_world;
  std::vector<bool> inliers;
  int num_inliers = 0;
  int iterations = 0;
};

// points_world[i] is observed at undistorted pixel pixels[i]; pixel_scales (may be empty)
// multiplies the threshold per match (pyramid scale factor of the keypoint).
PnpRansacResult EstimatePnpRansac(const std::vector<Vec3>& points_world, const std::vector<Vec2>& pixels,
                                  const PinholeCamera& camera, const PnpRansacOptions& options,
                                  const std::vector<double>& pixel_scales = {});

}  // namespace esdslam
