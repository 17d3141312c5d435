#pragma once
// Geometric verification of a place-recognition candidate from 3-D/3-D matches (both keyframes
// have metric depth): RANSAC over minimal 3-point closed-form alignments (Horn / Umeyama),
// refined by least squares on the inliers. RGB-D is metric, so the scale is fixed to 1 unless
// `estimate_scale` is set.

#include <cstdint>
#include <vector>

#include "camera/pinhole_camera.h"
#include "common/geometry.h"

namespace esdslam {

// p_a = scale * (rotation * p_b) + translation.
struct Sim3Transform {
  Rigid3 rigid;  // rotation and translation
  double scale = 1.0;

  Vec3 operator*(const Vec3& point) const { return scale * (rigid.rotation() * point) + rigid.translation(); }
  Sim3Transform inverse() const;
};

// Least-squares similarity (or rigid transform when !estimate_scale) a_from_b minimising
// sum |p_a - T p_b|^2 (Umeyama 1991). Needs >= 3 pairs not all collinear; returns false when
// degenerate.
bool AlignPointSets(const std::vector<Vec3>& points_a, const std::vector<Vec3>& points_b, bool estimate_scale,
                    Sim3Transform* a_from_b);

struct PointMatch3D {
  Vec3 point_a = Vec3::Zero();  // in frame a (metres)
  Vec3 point_b = Vec3::Zero();  // in frame b (metres)
  // Undistorted pixels where the points are observed (reprojection mode only), and threshold
  // multipliers (the keypoints' pyramid scale factors; 1 at level 0).
  Vec2 pixel_a = Vec2::Zero();
  Vec2 pixel_b = Vec2::Zero();
  double pixel_scale_a = 1.0;
  double pixel_scale_b = 1.0;
};

struct RigidRansacOptions {
  // kMetric: inlier when |p_a - T p_b| < max_error_m. kReprojection: inlier when T p_b projects
  // into view a within max_error_px * pixel_scale_a of pixel_a AND T^-1 p_a projects into view b
  // within max_error_px * pixel_scale_b of pixel_b (ORB-SLAM2's Sim3 check, chi2(2, 0.99) = 9.21
  // -> 3.03 px).
  enum class ErrorMode { kMetric, kReprojection };
  ErrorMode mode = ErrorMode::kReprojection;
  double max_error_m = 0.05;
  double max_error_px = 3.03;
  bool estimate_scale = false;
  double confidence = 0.99;  // adaptive stop: P(at least one all-inlier sample)
  int max_iterations = 300;
  int min_inliers = 20;      // ORB-SLAM2 accepts a loop Sim3 with >= 20 inliers
  int refine_rounds = 5;     // re-fit on inliers / re-select until stable
  std::uint32_t seed = 1;

  void Check() const;
};

struct RigidRansacResult {
  bool success = false;  // num_inliers >= min_inliers
  Sim3Transform a_from_b;
  std::vector<bool> inliers;  // per match
  int num_inliers = 0;
  int iterations = 0;
};

// camera_a / camera_b: required in kReprojection mode (may be the same camera), ignored otherwise.
RigidRansacResult EstimateRigidRansac(const std::vector<PointMatch3D>& matches, const RigidRansacOptions& options,
                                      const PinholeCamera* camera_a = nullptr, const PinholeCamera* camera_b = nullptr);

}  // namespace esdslam
