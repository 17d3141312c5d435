#include "dynamic/geometry_check.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "common/error.h"

namespace esdslam {
namespace {

double Threshold(double z, const GeometryCheckOptions& options) {
  return options.abs_threshold_m + options.depth_sq_threshold * z * z;
}

// Smallest and largest valid depth in the window around `pixel`; false if none is valid.
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

double ParallaxDeg(const Vec3& point, const Vec3& centre_a, const Vec3& centre_b) {
  const Vec3 a = point - centre_a, b = point - centre_b;
  const double cosine = a.dot(b) / std::max(1e-12, a.norm() * b.norm());
  return std::acos(std::clamp(cosine, -1.0, 1.0)) * 180.0 / M_PI;
}

// Whether the current pixel's 3-D point (the occluder) was already there when the reference
// keyframes were taken: at least one keyframe depth image confirms it (measured within tau of
// its expected depth) and none contradicts it (measured clearly behind it: that keyframe saw
// through the place where the occluder is now). Then the occlusion is due to the viewpoint
// change, not to motion. Keyframes without depth or not seeing the point abstain.
bool OccluderIsStatic(const PinholeCamera& camera, const std::vector<ReferenceKeyframe>& keyframes,
                      const Vec3& occluder_world, const GeometryCheckOptions& options) {
  int confirmations = 0;
  for (const ReferenceKeyframe& keyframe : keyframes) {
    if (keyframe.depth_m.empty()) continue;
    const Vec3 in_keyframe = keyframe.world_from_cam.inverse() * occluder_world;
    if (in_keyframe.z() < options.min_depth_m) continue;
    const Vec2 projected = camera.Project(in_keyframe);
    const cv::Point pixel(static_cast<int>(std::lround(projected.x())), static_cast<int>(std::lround(projected.y())));
    if (pixel.x < 0 || pixel.y < 0 || pixel.x >= keyframe.depth_m.cols || pixel.y >= keyframe.depth_m.rows) continue;
    float near, far;
    if (!WindowDepthRange(keyframe.depth_m, pixel, options.window_radius_px, &near, &far)) continue;
    const double tolerance = Threshold(in_keyframe.z(), options);
    if (near - in_keyframe.z() > tolerance) return false;  // seen through: it moved in since
    if (near - tolerance <= in_keyframe.z() && in_keyframe.z() <= far + tolerance) ++confirmations;
  }
  return confirmations > 0;
}

void TestKeyframePoints(const PinholeCamera& camera, const Rigid3& cam_from_world, const cv::Mat& depth_m,
                        const std::vector<ReferenceKeyframe>& keyframes, int k, const GeometryCheckOptions& options,
                        GeometryCheckResult& result) {
  const ReferenceKeyframe& keyframe = keyframes[k];
  const Rigid3 world_from_cam = cam_from_world.inverse();
  const int r = options.window_radius_px;
  for (int i = 0; i < static_cast<int>(keyframe.points_world.size()); ++i) {
    const Vec3& point = keyframe.points_world[i];
    const Vec3 in_cam = cam_from_world * point;
    const double z_proj = in_cam.z();
    if (z_proj < options.min_depth_m || z_proj > options.max_depth_m) continue;
    const Vec2 projected = camera.Project(in_cam);
    const cv::Point pixel(static_cast<int>(std::lround(projected.x())), static_cast<int>(std::lround(projected.y())));
    if (pixel.x < r || pixel.y < r || pixel.x >= depth_m.cols - r || pixel.y >= depth_m.rows - r) continue;
    if (ParallaxDeg(point, keyframe.world_from_cam.translation(), world_from_cam.translation()) >
        options.max_parallax_deg) {
      ++result.num_parallax_skipped;
      continue;
    }
    float near, far;
    if (!WindowDepthRange(depth_m, pixel, r, &near, &far)) continue;
    ++result.num_tested;
    const double tau = Threshold(z_proj, options);
    const float measured = depth_m.at<float>(pixel) > 0 ? depth_m.at<float>(pixel) : far;
    const FlaggedPoint flag{k, i, pixel, z_proj, measured};
    if (z_proj - far > tau) {
      const Vec3 occluder = world_from_cam * camera.Backproject(Vec2(pixel.x, pixel.y), measured);
      if (!OccluderIsStatic(camera, keyframes, occluder, options)) result.dynamic_points.push_back(flag);
    } else if (near - z_proj > tau) {
      result.vanished_points.push_back(flag);
    }
  }
}

// Region growing from clusters of flagged pixels, within mask_radius_px of the cluster's flags.
cv::Mat MaskFromFlags(const cv::Mat& depth_m, const std::vector<FlaggedPoint>& flags, const GeometryCheckOptions& options) {
  cv::Mat mask = cv::Mat::zeros(depth_m.size(), CV_8U);
  if (flags.empty()) return mask;
  cv::Mat discs = cv::Mat::zeros(depth_m.size(), CV_8U);
  for (const auto& flag : flags) cv::circle(discs, flag.pixel, options.cluster_radius_px / 2, 255, cv::FILLED);
  cv::Mat labels, stats, centroids;
  const int num_labels = cv::connectedComponentsWithStats(discs, labels, stats, centroids, 8, CV_32S);
  std::vector<std::vector<cv::Point>> seeds(num_labels);
  std::vector<std::vector<float>> depths(num_labels);
  for (const auto& flag : flags) {
    const int label = labels.at<int>(flag.pixel);
    seeds[label].push_back(flag.pixel);
    depths[label].push_back(static_cast<float>(flag.measured_depth_m));
  }
  const cv::Rect image(0, 0, depth_m.cols, depth_m.rows);
  const int radius = options.mask_radius_px;
  cv::Mat allowed = cv::Mat::zeros(depth_m.size(), CV_8U);
  for (int label = 1; label < num_labels; ++label) {
    if (static_cast<int>(seeds[label].size()) < options.min_cluster_points) continue;
    for (const auto& seed : seeds[label]) cv::circle(allowed, seed, radius, 255, cv::FILLED);
  }
  for (int label = 1; label < num_labels; ++label) {
    if (static_cast<int>(seeds[label].size()) < options.min_cluster_points) continue;
    const cv::Rect cluster(stats.at<int>(label, cv::CC_STAT_LEFT), stats.at<int>(label, cv::CC_STAT_TOP),
                           stats.at<int>(label, cv::CC_STAT_WIDTH), stats.at<int>(label, cv::CC_STAT_HEIGHT));
    const cv::Rect box =
        cv::Rect(cluster.x - radius, cluster.y - radius, cluster.width + 2 * radius, cluster.height + 2 * radius) & image;
    auto& d = depths[label];
    std::nth_element(d.begin(), d.begin() + d.size() / 2, d.end());
    GrowDepthRegion(depth_m, seeds[label], box, d[d.size() / 2], options.growing, mask, allowed);
  }
  return mask;
}

}  // namespace

void GeometryCheckOptions::Check() const {
  if (!(max_parallax_deg > 0 && max_parallax_deg <= 180)) throw Error("geometry check: max_parallax_deg must be in (0, 180]");
  if (!(abs_threshold_m > 0) || !(depth_sq_threshold >= 0))
    throw Error("geometry check: abs_threshold_m must be > 0 and depth_sq_threshold >= 0");
  if (!(min_depth_m >= 0 && max_depth_m > min_depth_m)) throw Error("geometry check: need 0 <= min_depth_m < max_depth_m");
  if (window_radius_px < 0 || cluster_radius_px < 1 || min_cluster_points < 1 || mask_radius_px < 1)
    throw Error("geometry check: need window_radius_px >= 0 and cluster_radius_px, min_cluster_points, mask_radius_px >= 1");
  growing.Check();
}

GeometryCheckResult CheckMultiViewGeometry(const PinholeCamera& camera, const Rigid3& cam_from_world,
                                           const cv::Mat& depth_m, const std::vector<ReferenceKeyframe>& keyframes,
                                           const GeometryCheckOptions& options) {
  if (depth_m.type() != CV_32F || depth_m.cols != camera.width() || depth_m.rows != camera.height())
    throw Error("CheckMultiViewGeometry: depth must be CV_32F with the camera's image size");
  GeometryCheckResult result;
  for (int k = 0; k < static_cast<int>(keyframes.size()); ++k)
    TestKeyframePoints(camera, cam_from_world, depth_m, keyframes, k, options, result);
  result.dynamic_mask = MaskFromFlags(depth_m, result.dynamic_points, options);
  return result;
}

}  // namespace esdslam
