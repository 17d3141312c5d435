#include "dense/map_render.h"

#include <algorithm>
#include <cmath>
#include <limits>

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

cv::Mat RenderTopView(const PointCloud& cloud, const std::vector<Rigid3>& world_from_cams, const MapRenderOptions& options) {
  const ViewFrame frame = EstimateViewFrame(world_from_cams);
  double max_cam_height = -std::numeric_limits<double>::infinity();
  for (const Rigid3& pose : world_from_cams) max_cam_height = std::max(max_cam_height, (pose.translation() - frame.centre).dot(frame.up));
  if (world_from_cams.empty()) max_cam_height = 0;
  const double clip_height = max_cam_height + options.ceiling_margin;
  // Plane coordinates (right, forward) and height of every kept point.
  std::vector<cv::Point2d> plane;
  std::vector<double> heights;
  std::vector<std::size_t> index;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Vec3 p = cloud.points[i].cast<double>() - frame.centre;
    const double h = p.dot(frame.up);
    if (h > clip_height) continue;
    plane.emplace_back(p.dot(frame.right), p.dot(frame.forward));
    heights.push_back(h);
    index.push_back(i);
  }
  cv::Mat image(options.height, options.width, CV_8UC3, cv::Scalar(30, 30, 30));
  if (plane.empty()) return image;
  cv::Rect2d bounds(plane[0], cv::Size2d(0, 0));
  for (const auto& q : plane) bounds |= cv::Rect2d(q, cv::Size2d(1e-9, 1e-9));
  const double scale = 0.95 * std::min(options.width / std::max(bounds.width, 1e-6), options.height / std::max(bounds.height, 1e-6));
  const auto to_pixel = [&](double x, double y) {
    return cv::Point(static_cast<int>(options.width / 2.0 + (x - (bounds.x + bounds.width / 2)) * scale),
                     static_cast<int>(options.height / 2.0 - (y - (bounds.y + bounds.height / 2)) * scale));
  };
  const double min_h = *std::min_element(heights.begin(), heights.end());
  const HeightPalette palette;
  const int radius = std::max(options.splat_px, static_cast<int>(std::ceil(0.5 * options.point_spacing * scale)) + 1);
  cv::Mat zbuffer(options.height, options.width, CV_32F, cv::Scalar(std::numeric_limits<float>::infinity()));
  for (std::size_t k = 0; k < plane.size(); ++k) {
    const cv::Point px = to_pixel(plane[k].x, plane[k].y);
    Splat(&image, &zbuffer, px.x, px.y, static_cast<float>(-heights[k]), palette((heights[k] - min_h) / std::max(clip_height - min_h, 1e-6)), radius);
  }
  for (std::size_t i = 1; i < world_from_cams.size(); ++i) {
    const Vec3 a = world_from_cams[i - 1].translation() - frame.centre, b = world_from_cams[i].translation() - frame.centre;
    cv::line(image, to_pixel(a.dot(frame.right), a.dot(frame.forward)), to_pixel(b.dot(frame.right), b.dot(frame.forward)),
             cv::Scalar(255, 255, 255), 2, cv::LINE_AA);
  }
  // Scale bar: 1 m.
  const int bar = static_cast<int>(scale);
  cv::line(image, {20, options.height - 20}, {20 + bar, options.height - 20}, cv::Scalar(255, 255, 255), 3);
  cv::putText(image, "1 m", {20, options.height - 30}, cv::FONT_HERSHEY_SIMPLEX, 0.6, cv::Scalar(255, 255, 255), 1, cv::LINE_AA);
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
