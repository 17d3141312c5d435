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
// separately (candidates for map-point culling). Seeing through X needs a depth reading at X's
// own pixel: where the sensor measures nothing there (dropouts on thin, dark or edge structures,
// common while the camera turns fast) the wall beside X says nothing about X, and it is not tested.
//
// Threshold: tau(z) = abs_threshold_m + depth_sq_threshold * z^2 (metres); DynaSLAM uses a
// fixed 0.4 m; depth noise and pose error both grow with depth, so we let tau grow with z^2.
// The measured depth is compared over a (2r+1)^2 window: flagged only if every valid depth in
// the window is in front (no flags from projections that land next to a depth edge). The window
// grows with the camera's image motion: colour and depth of consumer RGB-D sensors are exposed
// at slightly different times and read out by rolling shutters, so during fast motion the depth
// image is misregistered against the colour image's pose by a fraction of the motion between
// frames (TUM fr1_rpy at 60-140 deg/s: 10-20 px). r = window_radius_px + motion_window_fraction
// * image_motion_px; above max_window_radius_px the frame is not checked at all.
// If reference keyframes carry their depth images, a candidate pixel whose 3-D point (the
// occluder) some keyframe already saw at the same place, and no keyframe saw through, is a
// static occlusion (viewpoint change) and not flagged. An object sliding along its own surface
// can be confirmed by a recent keyframe, but older keyframes usually saw through it.
//
// The dynamic mask is grown from clusters of flags (dynamic/flag_mask.h).
//
// Pixel grids: points are projected with the ideal pinhole model (undistorted pixels); depth
// images are sensor images (raw, distorted pixels), so a projection is distorted before it is
// looked up (identity for cameras without distortion). Flags, the mask and FlaggedPoint::pixel
// are in the raw grid of the current depth image, like raw keypoint positions.

#include <cstdint>
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
  double depth_scale = 1.0;        // depth_m pixel = raw camera pixel * depth_scale (0.5: half size)
};

struct GeometryCheckOptions {
  double max_parallax_deg = 30.0;
  double abs_threshold_m = 0.08;     // tau(z) = abs_threshold_m + depth_sq_threshold * z^2
  double depth_sq_threshold = 0.02;  // 1/m
  double min_depth_m = 0.2;          // projected depths outside [min, max] are not tested
  double max_depth_m = 8.0;
  int window_radius_px = 1;          // measured depth window (2r+1)^2 without camera motion
  double motion_window_fraction = 0.5;  // ... plus this fraction of the image motion per frame
  int max_window_radius_px = 24;     // frames needing a larger window are not checked
  // Mask from the flags (dynamic/flag_mask.h).
  int cluster_radius_px = 24;
  int min_cluster_points = 3;
  double min_cluster_support = 0.5;  // covered / (covered + consistent) around a cluster's flags
  double mask_radius_m = 0.5;        // the mask grows only within this distance of a flagged pixel
  int max_mask_radius_px = 160;      // ... and within this many pixels
  // Growth of the mask from the flags: grown pixels stay within 0.4 m of the flags' median depth
  // (about a person's depth; person masks use 0.8 m, as their seeds cover more of the body).
  RegionGrowingOptions growing = [] {
    RegionGrowingOptions o;
    o.max_depth_from_seed_m = 0.4;
    return o;
  }();

  void Check() const;  // throws esdslam::Error
};

struct FlaggedPoint {
  int keyframe = 0;          // index into the reference keyframes
  int point = 0;             // index into its points_world
  cv::Point pixel;           // current image pixel the point projects to
  double projected_depth_m = 0;
  double measured_depth_m = 0;  // current depth at `pixel`
};

// What the check concluded about one reference point.
enum class PointOutcome : std::uint8_t {
  kUntested = 0,  // outside the image or depth range, or no valid depth around its projection
  kParallax,      // seen from too different a direction
  kConsistent,    // measured where expected (within tau)
  kCovered,       // something is now in front of it (-> FlaggedPoint in dynamic_points)
  kStaticOcclusion,  // covered, but the keyframes' depth shows the occluder was there before
  kExempt,        // covered at an exempt pixel (not used for the mask)
  kVanished,      // now seen through (-> vanished_points)
};

struct GeometryCheckResult {
  std::vector<FlaggedPoint> dynamic_points;   // current pixels covered by something that moved in
  std::vector<FlaggedPoint> vanished_points;  // reference points now seen through (they moved away)
  std::vector<cv::Point> static_pixels;       // where points were measured where expected (or vetoed)
  std::vector<std::vector<PointOutcome>> outcomes;  // [keyframe][point]
  cv::Mat dynamic_mask;                       // CV_8U, 255 = dynamic (current frame)
  int num_tested = 0;                         // points compared with a measured depth
  int num_parallax_skipped = 0;
  int window_radius_px = 0;                   // measured depth window used
  bool skipped_fast_motion = false;           // window above max_window_radius_px: nothing tested
};

// cam_from_world: current pose estimate; depth_m: current CV_32F depth (metres, 0 = invalid),
// raw pixel grid of `camera`. exempt: empty or CV_8U of the image size; covered points that
// project onto a nonzero pixel are not flagged (regions the caller trusts as static, or already
// knows to be dynamic), and the mask is cleared there. image_motion_px: how far the image moved
// since the previous frame (px, e.g. from the motion model). Throws Error on a wrong type or size.
GeometryCheckResult CheckMultiViewGeometry(const PinholeCamera& camera, const Rigid3& cam_from_world,
                                           const cv::Mat& depth_m, const std::vector<ReferenceKeyframe>& keyframes,
                                           const GeometryCheckOptions& options, const cv::Mat& exempt = cv::Mat(),
                                           double image_motion_px = 0);

// Image motion (px) between two poses of `camera` for a scene at scene_depth_m: f * (rotation
// angle + translation / depth).
double ImageMotionPx(const PinholeCamera& camera, const Rigid3& b_from_a, double scene_depth_m);

}  // namespace esdslam
