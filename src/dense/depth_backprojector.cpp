#include "dense/depth_backprojector.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "common/error.h"

namespace esdslam {

DepthBackprojector::DepthBackprojector(const PinholeCamera& camera, const DenseOptions& options)
    : camera_(camera), options_(options) {
  options_.Check();
  const int width = camera.width();
  const int height = camera.height();
  std::vector<cv::Point2f> pixels;
  pixels.reserve(static_cast<std::size_t>(width) * height);
  for (int v = 0; v < height; ++v)
    for (int u = 0; u < width; ++u) pixels.emplace_back(static_cast<float>(u), static_cast<float>(v));
  const std::vector<cv::Point2f> undistorted = camera.Undistort(pixels);
  ray_x_.create(height, width, CV_32F);
  ray_y_.create(height, width, CV_32F);
  for (int v = 0; v < height; ++v) {
    for (int u = 0; u < width; ++u) {
      const cv::Point2f& p = undistorted[static_cast<std::size_t>(v) * width + u];
      ray_x_.at<float>(v, u) = static_cast<float>((p.x - camera.cx()) / camera.fx());
      ray_y_.at<float>(v, u) = static_cast<float>((p.y - camera.cy()) / camera.fy());
    }
  }
  // Neighbouring rays one OctoMap cell apart at the OctoMap range.
  ray_stride_ = std::max(1, static_cast<int>(options.octomap_resolution * camera.fx() / options.octomap_max_range));
}

cv::Mat DepthBackprojector::ExclusionMask(const cv::Mat& dynamic_mask, cv::Size size) const {
  if (dynamic_mask.empty()) return cv::Mat::zeros(size, CV_8U);
  if (dynamic_mask.size() != size || dynamic_mask.type() != CV_8U)
    throw Error("dense: dynamic mask must be CV_8U with the depth image's size");
  cv::Mat binary = dynamic_mask > 0;
  if (options_.mask_dilation_px <= 0) return binary;
  // A radius past the image's diagonal (+2 px kernel rounding) covers the whole image from any
  // pixel: the result is known without building the (2r+1)^2 kernel (a setting cannot ask for GBs).
  if (options_.mask_dilation_px >= std::hypot(size.width, size.height) + 2)
    return cv::countNonZero(binary) > 0 ? cv::Mat(size, CV_8U, cv::Scalar(255)) : cv::Mat::zeros(size, CV_8U);
  const int k = 2 * options_.mask_dilation_px + 1;
  cv::Mat dilated;
  cv::dilate(binary, dilated, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(k, k)));
  return dilated;
}

cv::Mat DepthBackprojector::DepthEdges(const cv::Mat& depth_m) const {
  if (options_.edge_filter_px <= 0) return cv::Mat::zeros(depth_m.size(), CV_8U);
  // Farthest valid depth in the window (invalid pixels count as 0: the shadows that structured
  // light casts beside silhouettes say nothing about the pixel).
  cv::Mat depth_or_zero = cv::Mat::zeros(depth_m.size(), CV_32F), farthest;
  depth_m.copyTo(depth_or_zero, depth_m > 0);  // NaN compares false
  const int k = 2 * options_.edge_filter_px + 1;
  cv::dilate(depth_or_zero, farthest, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(k, k)));
  const float ratio = static_cast<float>(options_.edge_jump_ratio);
  cv::Mat edges(depth_m.size(), CV_8U);
  for (int v = 0; v < depth_m.rows; ++v) {
    const float* z = depth_or_zero.ptr<float>(v);
    const float* far = farthest.ptr<float>(v);
    std::uint8_t* edge = edges.ptr<std::uint8_t>(v);
    for (int u = 0; u < depth_m.cols; ++u) edge[u] = z[u] > 0 && far[u] - z[u] > ratio * z[u];
  }
  return edges;
}

KeyframeObservation DepthBackprojector::Observe(const cv::Mat& bgr, const cv::Mat& depth_m, const cv::Mat& dynamic_mask) const {
  if (depth_m.type() != CV_32F || bgr.type() != CV_8UC3 || depth_m.size() != bgr.size())
    throw Error("dense: expected CV_8UC3 colour and CV_32F depth of the same size");
  if (depth_m.cols != ray_x_.cols || depth_m.rows != ray_x_.rows)
    throw Error(fmt::format("dense: image is {}x{} but the camera is {}x{}", depth_m.cols, depth_m.rows, ray_x_.cols, ray_x_.rows));
  const cv::Mat excluded = ExclusionMask(dynamic_mask, depth_m.size());
  KeyframeObservation observation;
  observation.points_cam = BackprojectPixels(bgr, depth_m, excluded | DepthEdges(depth_m));
  observation.rays = SampleRays(depth_m, excluded);
  return observation;
}

PointCloud DepthBackprojector::BackprojectPixels(const cv::Mat& bgr, const cv::Mat& depth_m, const cv::Mat& excluded) const {
  const int stride = options_.pixel_stride;
  PointCloud cloud;
  cloud.reserve(static_cast<std::size_t>((depth_m.rows + stride - 1) / stride) * ((depth_m.cols + stride - 1) / stride));
  for (int v = 0; v < depth_m.rows; v += stride) {
    const float* depth_row = depth_m.ptr<float>(v);
    const std::uint8_t* excluded_row = excluded.ptr<std::uint8_t>(v);
    const cv::Vec3b* color_row = bgr.ptr<cv::Vec3b>(v);
    for (int u = 0; u < depth_m.cols; u += stride) {
      const float z = depth_row[u];
      if (!std::isfinite(z) || z < options_.min_depth || z > options_.max_depth || excluded_row[u]) continue;
      const cv::Vec3b& c = color_row[u];
      cloud.push_back(Point(u, v, z), Rgb8{c[2], c[1], c[0]});
    }
  }
  return cloud;
}

KeyframeRays DepthBackprojector::SampleRays(const cv::Mat& depth_m, const cv::Mat& excluded) const {
  KeyframeRays rays;
  rays.stride = ray_stride_;
  rays.depth_mm = cv::Mat::zeros((depth_m.rows + ray_stride_ - 1) / ray_stride_, (depth_m.cols + ray_stride_ - 1) / ray_stride_, CV_16U);
  for (int r = 0; r < rays.depth_mm.rows; ++r) {
    for (int c = 0; c < rays.depth_mm.cols; ++c) {
      const int u = c * ray_stride_, v = r * ray_stride_;
      const float z = depth_m.at<float>(v, u);
      if (!std::isfinite(z) || z < options_.min_depth || excluded.at<std::uint8_t>(v, u)) continue;
      rays.depth_mm.at<std::uint16_t>(r, c) = static_cast<std::uint16_t>(std::min(65535.0f, std::round(1000.0f * z)));
    }
  }
  return rays;
}

std::vector<Eigen::Vector3f> DepthBackprojector::RayEndpoints(const KeyframeRays& rays) const {
  std::vector<Eigen::Vector3f> endpoints;
  for (int r = 0; r < rays.depth_mm.rows; ++r)
    for (int c = 0; c < rays.depth_mm.cols; ++c) {
      const std::uint16_t mm = rays.depth_mm.at<std::uint16_t>(r, c);
      if (mm > 0) endpoints.push_back(Point(c * rays.stride, r * rays.stride, 0.001f * mm));
    }
  return endpoints;
}

}  // namespace esdslam
