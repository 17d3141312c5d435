#include "dense/depth_backprojector.h"

#include <opencv2/imgproc.hpp>

#include "common/error.h"
#include "dense/voxel_grid.h"

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
}

cv::Mat DepthBackprojector::ExclusionMask(const cv::Mat& dynamic_mask, cv::Size size) const {
  if (dynamic_mask.empty()) return cv::Mat::zeros(size, CV_8U);
  if (dynamic_mask.size() != size || dynamic_mask.type() != CV_8U)
    throw Error("dense: dynamic mask must be CV_8U with the depth image's size");
  cv::Mat binary = dynamic_mask > 0;
  if (options_.mask_dilation_px <= 0) return binary;
  const int k = 2 * options_.mask_dilation_px + 1;
  cv::Mat dilated;
  cv::dilate(binary, dilated, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(k, k)));
  return dilated;
}

PointCloud DepthBackprojector::Backproject(const cv::Mat& bgr, const cv::Mat& depth_m, const cv::Mat& dynamic_mask) const {
  if (depth_m.type() != CV_32F || bgr.type() != CV_8UC3 || depth_m.size() != bgr.size())
    throw Error("dense: expected CV_8UC3 colour and CV_32F depth of the same size");
  if (depth_m.cols != ray_x_.cols || depth_m.rows != ray_x_.rows)
    throw Error(fmt::format("dense: image is {}x{} but the camera is {}x{}", depth_m.cols, depth_m.rows, ray_x_.cols, ray_x_.rows));
  const cv::Mat excluded = ExclusionMask(dynamic_mask, depth_m.size());
  VoxelGrid grid(options_.voxel_size);
  const int stride = options_.pixel_stride;
  for (int v = 0; v < depth_m.rows; v += stride) {
    const float* depth_row = depth_m.ptr<float>(v);
    const std::uint8_t* excluded_row = excluded.ptr<std::uint8_t>(v);
    const cv::Vec3b* color_row = bgr.ptr<cv::Vec3b>(v);
    for (int u = 0; u < depth_m.cols; u += stride) {
      const float z = depth_row[u];
      if (!std::isfinite(z) || z < options_.min_depth || z > options_.max_depth || excluded_row[u]) continue;
      const Eigen::Vector3f point(ray_x_.at<float>(v, u) * z, ray_y_.at<float>(v, u) * z, z);
      const cv::Vec3b& c = color_row[u];
      grid.Insert(point, Rgb8{c[2], c[1], c[0]});
    }
  }
  return grid.Extract();
}

}  // namespace esdslam
