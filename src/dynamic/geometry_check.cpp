#include "dynamic/geometry_check.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <opencv2/imgproc.hpp>

#include "common/error.h"
#include "common/setting_error.h"
#include "dynamic/depth_window.h"
#include "dynamic/flag_mask.h"

namespace esdslam {
namespace {

double Threshold(double z, const GeometryCheckOptions& options) {
  return options.abs_threshold_m + options.depth_sq_threshold * z * z;
}

// Smallest and largest valid depth in the window around `pixel` (read directly: used for the
// few covered points only); false if none is valid.
bool WindowDepthRange(const cv::Mat& depth_m, const cv::Point& pixel, int radius, float* near, float* far) {
  *near = std::numeric_limits<float>::infinity();
  *far = 0.f;
  for (int v = std::max(0, pixel.y - radius); v <= std::min(depth_m.rows - 1, pixel.y + radius); ++v) {
    const float* row = depth_m.ptr<float>(v);
    for (int u = std::max(0, pixel.x - radius); u <= std::min(depth_m.cols - 1, pixel.x + radius); ++u) {
      if (!(row[u] > 0)) continue;
      *near = std::min(*near, row[u]);
      *far = std::max(*far, row[u]);
    }
  }
  return *far > 0;
}

// Whether the rays centre_a -> point and centre_b -> point differ by more than the angle whose
// cosine is min_cosine.
bool LargeParallax(const Vec3& point, const Vec3& centre_a, const Vec3& centre_b, double min_cosine) {
  const Vec3 a = point - centre_a, b = point - centre_b;
  return a.dot(b) < min_cosine * std::sqrt(a.squaredNorm() * b.squaredNorm());
}

// The raw (sensor) pixel of an ideal projection, in an image scaled by `scale`.
cv::Point RawPixel(const PinholeCamera& camera, const Vec2& undistorted, double scale = 1.0) {
  const Vec2 raw = camera.intrinsics().HasDistortion() ? camera.Distort(undistorted) : undistorted;
  return {static_cast<int>(std::lround(raw.x() * scale)), static_cast<int>(std::lround(raw.y() * scale))};
}

// Whether the current pixel's 3-D point (the occluder) was already there when the reference
// keyframes were taken: at least one keyframe depth image confirms it (measured within tau of
// its expected depth) and none contradicts it (measured clearly behind it: that keyframe saw
// through the place where the occluder is now). Then the occlusion is due to the viewpoint
// change, not to motion. Keyframes without depth or not seeing the point abstain. The keyframe
// depth is read over the current window (scaled): keyframes were misregistered as much.
bool OccluderIsStatic(const PinholeCamera& camera, const std::vector<ReferenceKeyframe>& keyframes,
                      const Vec3& occluder_world, int window_radius_px, const GeometryCheckOptions& options) {
  int confirmations = 0;
  for (const ReferenceKeyframe& keyframe : keyframes) {
    if (keyframe.depth_m.empty()) continue;
    const Vec3 in_keyframe = keyframe.world_from_cam.inverse() * occluder_world;
    if (in_keyframe.z() < options.min_depth_m) continue;
    const cv::Point pixel = RawPixel(camera, camera.Project(in_keyframe), keyframe.depth_scale);
    if (pixel.x < 0 || pixel.y < 0 || pixel.x >= keyframe.depth_m.cols || pixel.y >= keyframe.depth_m.rows) continue;
    float near, far;
    const int radius = std::max(options.window_radius_px,
                                static_cast<int>(std::lround(window_radius_px * keyframe.depth_scale)));
    if (!WindowDepthRange(keyframe.depth_m, pixel, radius, &near, &far)) continue;
    const double tolerance = Threshold(in_keyframe.z(), options);
    if (near - in_keyframe.z() > tolerance) return false;  // seen through: it moved in since
    if (near - tolerance <= in_keyframe.z() && in_keyframe.z() <= far + tolerance) ++confirmations;
  }
  return confirmations > 0;
}

struct CurrentView {
  const PinholeCamera& camera;
  Rigid3 cam_from_world, world_from_cam;
  const cv::Mat& depth_m;
  const DepthWindow& window;
  const cv::Mat& exempt;
  double min_parallax_cosine;
};

// Tests one reference point against the current depth; fills `flag` for covered / vanished.
PointOutcome TestPoint(const CurrentView& view, const std::vector<ReferenceKeyframe>& keyframes, int k,
                       const Vec3& point, const GeometryCheckOptions& options, FlaggedPoint* flag) {
  const Vec3 in_cam = view.cam_from_world * point;
  const double z_proj = in_cam.z();
  if (z_proj < options.min_depth_m || z_proj > options.max_depth_m) return PointOutcome::kUntested;
  const Vec2 projected = view.camera.Project(in_cam);
  const cv::Point pixel = RawPixel(view.camera, projected);
  const int r = options.window_radius_px;
  if (pixel.x < r || pixel.y < r || pixel.x >= view.depth_m.cols - r || pixel.y >= view.depth_m.rows - r)
    return PointOutcome::kUntested;
  if (LargeParallax(point, keyframes[k].world_from_cam.translation(), view.world_from_cam.translation(),
                    view.min_parallax_cosine))
    return PointOutcome::kParallax;
  float near, far;
  if (!view.window.Range(pixel, &near, &far)) return PointOutcome::kUntested;
  const double tau = Threshold(z_proj, options);
  const float at_pixel = view.depth_m.at<float>(pixel);  // 0: no reading at the point's own pixel
  const float measured = at_pixel > 0 ? at_pixel : far;
  flag->pixel = pixel;
  flag->projected_depth_m = z_proj;
  flag->measured_depth_m = measured;
  if (near - z_proj > tau)  // seen through only where X's own pixel has a reading (header)
    return at_pixel > 0 ? PointOutcome::kVanished : PointOutcome::kUntested;
  if (z_proj - far <= tau) return PointOutcome::kConsistent;
  if (!view.exempt.empty() && view.exempt.at<std::uint8_t>(pixel)) return PointOutcome::kExempt;
  // The occluder lies on the same viewing ray, at the measured depth.
  const Vec3 occluder = view.world_from_cam * view.camera.Backproject(projected, measured);
  const bool static_occlusion = OccluderIsStatic(view.camera, keyframes, occluder, view.window.radius(), options);
  return static_occlusion ? PointOutcome::kStaticOcclusion : PointOutcome::kCovered;
}

void TestKeyframePoints(const CurrentView& view, const std::vector<ReferenceKeyframe>& keyframes, int k,
                        const GeometryCheckOptions& options, GeometryCheckResult& result) {
  const std::vector<Vec3>& points = keyframes[k].points_world;
  std::vector<PointOutcome>& outcomes = result.outcomes[k];
  for (int i = 0; i < static_cast<int>(points.size()); ++i) {
    FlaggedPoint flag{k, i, cv::Point(), 0, 0};
    const PointOutcome outcome = TestPoint(view, keyframes, k, points[i], options, &flag);
    outcomes[i] = outcome;
    if (outcome == PointOutcome::kParallax) ++result.num_parallax_skipped;
    if (outcome != PointOutcome::kUntested && outcome != PointOutcome::kParallax) ++result.num_tested;
    if (outcome == PointOutcome::kCovered) result.dynamic_points.push_back(flag);
    if (outcome == PointOutcome::kVanished) result.vanished_points.push_back(flag);
    if (outcome == PointOutcome::kConsistent || outcome == PointOutcome::kStaticOcclusion)
      result.static_pixels.push_back(flag.pixel);
  }
}

}  // namespace

void GeometryCheckOptions::Check() const {
  const std::string k = "Dynamic.check.";
  CheckRange(k + "maxParallax", max_parallax_deg, 0.1, 180.0, "deg");
  CheckRange(k + "absThreshold", abs_threshold_m, 1e-4, 2.0, "m");
  CheckRange(k + "depthSqThreshold", depth_sq_threshold, 0.0, 1.0, "1/m");
  CheckRange(k + "minDepth", min_depth_m, 0.0, 100.0, "m");
  CheckRange(k + "maxDepth", max_depth_m, min_depth_m + 1e-3, 100.0, "m");
  CheckRange(k + "windowRadius", window_radius_px, 0, 50, "px");
  CheckRange(k + "motionWindowFraction", motion_window_fraction, 0.0, 10.0);
  CheckRange(k + "maxWindowRadius", max_window_radius_px, window_radius_px, 100, "px");
  CheckRange(k + "clusterRadius", cluster_radius_px, 1, 500, "px");
  CheckRange(k + "minClusterPoints", min_cluster_points, 1, 10000);
  CheckRange(k + "minClusterSupport", min_cluster_support, 0.0, 1.0);
  CheckRange(k + "maskRadius", mask_radius_m, 1e-3, 10.0, "m");
  CheckRange(k + "maxMaskRadius", max_mask_radius_px, cluster_radius_px, 2000, "px");
  growing.Check(k + "grow.");
}

GeometryCheckResult CheckMultiViewGeometry(const PinholeCamera& camera, const Rigid3& cam_from_world,
                                           const cv::Mat& depth_m, const std::vector<ReferenceKeyframe>& keyframes,
                                           const GeometryCheckOptions& options, const cv::Mat& exempt,
                                           double image_motion_px) {
  if (depth_m.type() != CV_32F || depth_m.cols != camera.width() || depth_m.rows != camera.height())
    throw Error("CheckMultiViewGeometry: depth must be CV_32F with the camera's image size");
  if (!exempt.empty() && (exempt.type() != CV_8U || exempt.size() != depth_m.size()))
    throw Error("CheckMultiViewGeometry: the exempt mask must be CV_8U with the depth image's size");
  for (const ReferenceKeyframe& keyframe : keyframes) {
    if (!keyframe.depth_m.empty() && (keyframe.depth_m.type() != CV_32F || !(keyframe.depth_scale > 0)))
      throw Error("CheckMultiViewGeometry: keyframe depth must be CV_32F with a positive depth_scale");
  }
  GeometryCheckResult result;
  result.outcomes.resize(keyframes.size());
  for (std::size_t k = 0; k < keyframes.size(); ++k)
    result.outcomes[k].assign(keyframes[k].points_world.size(), PointOutcome::kUntested);
  const double motion_px = std::max(0.0, image_motion_px);
  result.window_radius_px =
      options.window_radius_px + static_cast<int>(std::ceil(options.motion_window_fraction * motion_px));
  if (result.window_radius_px > options.max_window_radius_px) {
    result.skipped_fast_motion = true;
    result.dynamic_mask = cv::Mat::zeros(depth_m.size(), CV_8U);
    return result;
  }
  const DepthWindow window(depth_m, result.window_radius_px);
  const CurrentView view{camera, cam_from_world, cam_from_world.inverse(), depth_m, window, exempt,
                         std::cos(options.max_parallax_deg * M_PI / 180.0)};
  for (int k = 0; k < static_cast<int>(keyframes.size()); ++k) TestKeyframePoints(view, keyframes, k, options, result);
  result.dynamic_mask = MaskFromFlags(camera, depth_m, result.dynamic_points, result.static_pixels, options);
  if (!exempt.empty()) result.dynamic_mask.setTo(0, exempt);
  return result;
}

double ImageMotionPx(const PinholeCamera& camera, const Rigid3& b_from_a, double scene_depth_m) {
  const double angle = RotationAngle(b_from_a.rotation());
  return camera.fx() * (angle + b_from_a.translation().norm() / std::max(scene_depth_m, 0.1));
}

}  // namespace esdslam
