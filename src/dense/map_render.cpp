#include "dense/map_render.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

namespace esdslam {

namespace {

// Orthonormal frame with `up` against gravity and `forward` the mean horizontal viewing direction.
struct ViewFrame {
  Vec3 up, forward, right, centre;
};

ViewFrame EstimateViewFrame(const std::vector<Rigid3>& world_from_cams) {
  Vec3 down = Vec3::Zero(), forward = Vec3::Zero(), centre = Vec3::Zero();
  for (const Rigid3& pose : world_from_cams) {
    down += pose.rotation() * Vec3::UnitY();
    forward += pose.rotation() * Vec3::UnitZ();
    centre += pose.translation();
  }
  ViewFrame frame;
  frame.up = down.norm() > 1e-9 ? Vec3(-down.normalized()) : Vec3(-Vec3::UnitY());
  Vec3 horizontal = forward - forward.dot(frame.up) * frame.up;
  if (horizontal.norm() < 1e-9) horizontal = frame.up.unitOrthogonal();
  frame.forward = horizontal.normalized();
  frame.right = frame.forward.cross(frame.up).normalized();
  frame.centre = world_from_cams.empty() ? Vec3::Zero() : Vec3(centre / static_cast<double>(world_from_cams.size()));
  return frame;
}

// Turbo colour map as a 256-entry lookup table (BGR).
class HeightPalette {
 public:
  HeightPalette() {
    cv::Mat1b ramp(1, 256);
    for (int i = 0; i < 256; ++i) ramp(0, i) = static_cast<std::uint8_t>(i);
    cv::applyColorMap(ramp, lut_, cv::COLORMAP_TURBO);
  }
  // t in [0, 1]; the darkest eighth of the map is skipped so low points stay visible on the dark background.
  cv::Vec3b operator()(double t) const { return lut_.at<cv::Vec3b>(0, 32 + static_cast<int>(std::clamp(t, 0.0, 1.0) * 223)); }

 private:
  cv::Mat lut_;
};

void Splat(cv::Mat* image, cv::Mat* zbuffer, int u, int v, float depth, const cv::Vec3b& color, int radius) {
  for (int dv = -radius + 1; dv < radius; ++dv)
    for (int du = -radius + 1; du < radius; ++du) {
      const int x = u + du, y = v + dv;
      if (x < 0 || y < 0 || x >= image->cols || y >= image->rows) continue;
      float& z = zbuffer->at<float>(y, x);
      if (depth >= z) continue;
      z = depth;
      image->at<cv::Vec3b>(y, x) = color;
    }
}

}  // namespace

namespace {

// Colour bar (height above the lowest point, metres) in the top-right corner.
void DrawHeightLegend(cv::Mat* image, const HeightPalette& palette, double min_h, double max_h) {
  const int x0 = image->cols - 40, y0 = 20, height = 160;
  for (int i = 0; i < height; ++i) {
    const cv::Vec3b c = palette(1.0 - static_cast<double>(i) / (height - 1));
    cv::line(*image, {x0, y0 + i}, {x0 + 16, y0 + i}, cv::Scalar(c[0], c[1], c[2]));
  }
  const cv::Scalar white(255, 255, 255);
  cv::putText(*image, fmt::format("{:.1f} m", max_h - min_h), {x0 - 58, y0 + 8}, cv::FONT_HERSHEY_SIMPLEX, 0.5, white, 1, cv::LINE_AA);
  cv::putText(*image, "0 m", {x0 - 34, y0 + height}, cv::FONT_HERSHEY_SIMPLEX, 0.5, white, 1, cv::LINE_AA);
  cv::putText(*image, "height", {x0 - 50, y0 + height + 22}, cv::FONT_HERSHEY_SIMPLEX, 0.5, white, 1, cv::LINE_AA);
}

// Camera path (white) with a dot per keyframe, and a 1 m scale bar.
void DrawCamerasAndScale(cv::Mat* image, const std::vector<cv::Point>& cams, double metres_to_px) {
  const cv::Scalar white(255, 255, 255);
  for (std::size_t i = 1; i < cams.size(); ++i) cv::line(*image, cams[i - 1], cams[i], white, 2, cv::LINE_AA);
  for (const cv::Point& c : cams) cv::circle(*image, c, 2, white, cv::FILLED, cv::LINE_AA);
  const int bar = static_cast<int>(metres_to_px);
  cv::line(*image, {20, image->rows - 20}, {20 + bar, image->rows - 20}, white, 3);
  cv::putText(*image, "1 m", {20, image->rows - 30}, cv::FONT_HERSHEY_SIMPLEX, 0.6, white, 1, cv::LINE_AA);
}

}  // namespace

cv::Mat RenderTopView(const PointCloud& cloud, const std::vector<Rigid3>& world_from_cams, const MapRenderOptions& options) {
  const ViewFrame frame = EstimateViewFrame(world_from_cams);
  double max_cam_height = -std::numeric_limits<double>::infinity();
  for (const Rigid3& pose : world_from_cams) max_cam_height = std::max(max_cam_height, (pose.translation() - frame.centre).dot(frame.up));
  if (world_from_cams.empty()) max_cam_height = 0;
  const double clip_height = max_cam_height + options.ceiling_margin;
  const auto plane_of = [&](const Vec3& p) { return cv::Point2d(p.dot(frame.right), p.dot(frame.forward)); };
  // Plane coordinates (right, forward) and height of every kept point.
  std::vector<cv::Point2d> plane;
  std::vector<double> heights;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Vec3 p = cloud.points[i].cast<double>() - frame.centre;
    const double h = p.dot(frame.up);
    if (h > clip_height) continue;
    plane.push_back(plane_of(p));
    heights.push_back(h);
  }
  cv::Mat image(options.height, options.width, CV_8UC3, cv::Scalar(30, 30, 30));
  if (plane.empty()) return image;
  std::vector<cv::Point2d> cams_plane;
  for (const Rigid3& pose : world_from_cams) cams_plane.push_back(plane_of(pose.translation() - frame.centre));
  cv::Rect2d bounds(plane[0], cv::Size2d(0, 0));
  for (const auto& q : plane) bounds |= cv::Rect2d(q, cv::Size2d(1e-9, 1e-9));
  for (const auto& q : cams_plane) bounds |= cv::Rect2d(q, cv::Size2d(1e-9, 1e-9));  // keep the cameras in view
  const double scale = 0.9 * std::min(options.width / std::max(bounds.width, 1e-6), options.height / std::max(bounds.height, 1e-6));
  const auto to_pixel = [&](const cv::Point2d& q) {
    return cv::Point(static_cast<int>(options.width / 2.0 + (q.x - (bounds.x + bounds.width / 2)) * scale),
                     static_cast<int>(options.height / 2.0 - (q.y - (bounds.y + bounds.height / 2)) * scale));
  };
  const double min_h = *std::min_element(heights.begin(), heights.end());
  const HeightPalette palette;
  const int radius = std::max(options.splat_px, static_cast<int>(std::ceil(0.5 * options.point_spacing * scale)) + 1);
  cv::Mat zbuffer(options.height, options.width, CV_32F, cv::Scalar(std::numeric_limits<float>::infinity()));
  for (std::size_t k = 0; k < plane.size(); ++k) {
    const cv::Point px = to_pixel(plane[k]);
    Splat(&image, &zbuffer, px.x, px.y, static_cast<float>(-heights[k]), palette((heights[k] - min_h) / std::max(clip_height - min_h, 1e-6)), radius);
  }
  std::vector<cv::Point> cams_px;
  for (const auto& q : cams_plane) cams_px.push_back(to_pixel(q));
  DrawCamerasAndScale(&image, cams_px, scale);
  DrawHeightLegend(&image, palette, min_h, clip_height);
  return image;
}

cv::Mat RenderPerspectiveView(const PointCloud& cloud, const std::vector<Rigid3>& world_from_cams, const MapRenderOptions& options) {
  const ViewFrame frame = EstimateViewFrame(world_from_cams);
  cv::Mat image(options.height, options.width, CV_8UC3, cv::Scalar(30, 30, 30));
  if (cloud.empty()) return image;
  Vec3 target = Vec3::Zero();
  for (const auto& p : cloud.points) target += p.cast<double>();
  target /= static_cast<double>(cloud.size());
  // Eye: behind the mean camera and above it; look at the map centre.
  const Vec3 eye = frame.centre - 1.5 * frame.forward + 1.2 * frame.up;
  const Vec3 z_axis = (target - eye).normalized();
  const Vec3 x_axis = z_axis.cross(frame.up).normalized();
  const Vec3 y_axis = z_axis.cross(x_axis);
  const double focal = 0.6 * options.width;
  cv::Mat zbuffer(options.height, options.width, CV_32F, cv::Scalar(std::numeric_limits<float>::infinity()));
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Vec3 d = cloud.points[i].cast<double>() - eye;
    const double z = d.dot(z_axis);
    if (z < 0.1) continue;
    const int u = static_cast<int>(options.width / 2.0 + focal * d.dot(x_axis) / z);
    const int v = static_cast<int>(options.height / 2.0 + focal * d.dot(y_axis) / z);
    const Rgb8& c = cloud.colors[i];
    Splat(&image, &zbuffer, u, v, static_cast<float>(z), cv::Vec3b(c.b, c.g, c.r), options.splat_px);
  }
  return image;
}

}  // namespace esdslam
