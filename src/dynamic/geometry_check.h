#pragma once
// Multi-view geometry check for moving objects (ESD-SLAM Algorithm 2, after DynaSLAM).
//
// Reference keyframes (up to 5, the ones overlapping most with the current frame) saw static
// 3-D points. Each point X is projected into the current frame with the current pose estimate:
// projected depth z_proj at pixel x. If the current depth image measures z at x clearly in
// front of X, z_proj - z > tau(z_proj), something new now covers X: the current pixel x is on a
// moving object. Points seen from too different directions (parallax angle between the rays
// keyframe-centre -> X and current-centre -> X above 30 deg) are skipped, since viewpoint
// changes then cause static self-occlusions. The opposite case, z - z_proj > tau (we now see
// through X), means X itself was on something that moved away; those points are reported
// separately (candidates for map-point culling).
//
// Threshold: tau(z) = abs_threshold_m + depth_sq_threshold * z^2 (metres); DynaSLAM uses a
// fixed 0.4 m; depth noise and pose error both grow with depth, so we let tau grow with z^2.
// The measured depth is compared over a (2r+1)^2 window: flagged only if every valid depth in
// the window is in front (no flags from projections that land next to a depth edge).
// If reference keyframes carry their depth images, a candidate pixel whose 3-D point (the
// occluder) some keyframe already saw at the same place, and no keyframe saw through, is a
// static occlusion (viewpoint change) and not flagged. An object sliding along its own surface
// can be confirmed by a recent keyframe, but older keyframes usually saw through it.
//
// The dynamic mask grows depth regions (dynamic/region_growing.h) from clusters of flagged
// pixels: flags within cluster_radius_px of each other form a cluster; clusters with fewer than
// min_cluster_points flags are ignored for the mask (isolated flags are usually noise). Growth
// stays within mask_radius_px of the cluster's flags (limits leaks into the floor at the feet).

#include <vector>

#include <opencv2/core.hpp>

#include "camera/pinhole_camera.h"
#include "common/geometry.h"
#include "dynamic/region_growing.h"

namespace esdslam {

struct ReferenceKeyframe {
  Rigid3 world_from_cam;
  std::vector<Vec3> points_world;  // 3-D points the keyframe observed (e.g. its map points)
  cv::Mat depth_m;                 // optional CV_32F depth of the keyframe (same camera); empty = none
};

struct GeometryCheckOptions {
  double max_parallax_deg = 30.0;
  double abs_threshold_m = 0.08;     // tau(z) = abs_threshold_m + depth_sq_threshold * z^2
  double depth_sq_threshold = 0.02;  // 1/m
  double min_depth_m = 0.2;          // projected depths outside [min, max] are not tested
  double max_depth_m = 8.0;
  int window_radius_px = 1;          // measured depth window (2r+1)^2
  int cluster_radius_px = 24;
  int min_cluster_points = 3;
  int mask_radius_px = 32;           // the mask grows only within this distance of a flagged pixel
  RegionGrowingOptions growing;

  void Check() const;  // throws esdslam::Error
};

struct FlaggedPoint {
  int keyframe = 0;          // index into the reference keyframes
  int point = 0;             // index into its points_world
  cv::Point pixel;           // current image pixel the point projects to
  double projected_depth_m = 0;
  double measured_depth_m = 0;  // current depth at `pixel`
};

struct GeometryCheckResult {
  std::vector<FlaggedPoint> dynamic_points;   // current pixels covered by something that moved in
  std::vector<FlaggedPoint> vanished_points;  // reference points now seen through (they moved away)
  cv::Mat dynamic_mask;                       // CV_8U, 255 = dynamic (current frame)
  int num_tested = 0;                         // points compared with a measured depth
  int num_parallax_skipped = 0;
};

// cam_from_world: current pose estimate; depth_m: current CV_32F depth (metres, 0 = invalid),
// undistorted pixel grid of `camera`. Throws Error on a wrong depth type or size.
GeometryCheckResult CheckMultiViewGeometry(const PinholeCamera& camera, const Rigid3& cam_from_world,
                                           const cv::Mat& depth_m, const std::vector<ReferenceKeyframe>& keyframes,
                                           const GeometryCheckOptions& options);

}  // namespace esdslam
