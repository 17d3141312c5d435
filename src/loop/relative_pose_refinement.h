#pragma once
// Refinement of the rigid transform between two keyframes from 3-D/3-D matches by reprojection
// (ORB-SLAM2's OptimizeSim3 with the scale fixed, as RGB-D is metric): each match contributes
// the reprojection of point_b through a_from_b into view a and of point_a through b_from_a into
// view b, weighted by the keypoints' pyramid scale (information 1 / pixel_scale^2). Levenberg-
// Marquardt with a Huber loss, outliers (chi2 > threshold) dropped, then more iterations on the
// inliers. Ceres, deterministic (one thread).

#include <vector>

#include "camera/pinhole_camera.h"
#include "robust/rigid_ransac.h"

namespace esdslam {

struct RelativePoseRefinementOptions {
  double chi2 = 10.0;         // per direction, 2 DoF (ORB-SLAM2's OptimizeSim3 threshold)
  int iterations_first = 5;   // with Huber, all matches
  int iterations_second = 10; // without the outliers (ORB-SLAM2: 10, or 5 when none were dropped)
  void Check() const;
};

// a_from_b: initial estimate in, refined estimate out. inliers (may be null): per match, both
// reprojections within chi2 after refinement (points behind a camera are outliers). Returns the
// inlier count.
int RefineRelativePose(const std::vector<PointMatch3D>& matches, const PinholeCamera& camera_a,
                       const PinholeCamera& camera_b, const RelativePoseRefinementOptions& options, Rigid3* a_from_b,
                       std::vector<bool>* inliers = nullptr);

}  // namespace esdslam
