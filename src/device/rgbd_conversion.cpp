#include "device/rgbd_conversion.h"

#include <cmath>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

#include "common/error.h"

namespace esdslam {
namespace {

void CheckBuffer(const void* data, int width, int height, std::size_t stride_bytes, std::size_t pixel_bytes,
                 const char* what) {
  if (data == nullptr || width <= 0 || height <= 0 || stride_bytes < static_cast<std::size_t>(width) * pixel_bytes)
    throw Error(fmt::format("{} image: bad buffer ({}x{}, stride {} bytes, {} bytes per pixel)", what, width, height,
                            stride_bytes, pixel_bytes));
}

}  // namespace

cv::Mat DepthMmToMetres(const std::uint16_t* depth_mm, int width, int height, std::size_t stride_bytes) {
  CheckBuffer(depth_mm, width, height, stride_bytes, sizeof(std::uint16_t), "depth");
  // Wrap the driver's buffer (not written), convert into our own image: 1 mm = 0.001 m, 0 stays 0.
  const cv::Mat raw(height, width, CV_16UC1, const_cast<std::uint16_t*>(depth_mm), stride_bytes);
  cv::Mat metres;
  raw.convertTo(metres, CV_32F, 1e-3);
  return metres;
}

cv::Mat Rgb888ToBgr(const std::uint8_t* rgb, int width, int height, std::size_t stride_bytes) {
  CheckBuffer(rgb, width, height, stride_bytes, 3, "colour");
  const cv::Mat raw(height, width, CV_8UC3, const_cast<std::uint8_t*>(rgb), stride_bytes);
  cv::Mat bgr;
  cv::cvtColor(raw, bgr, cv::COLOR_RGB2BGR);
  return bgr;
}

cv::Mat RegisterDepthToColour(const cv::Mat& depth_m, const CameraIntrinsics& depth_camera,
                              const CameraIntrinsics& colour_camera, const Rigid3& colour_from_depth) {
  if (depth_m.type() != CV_32F || depth_m.cols != depth_camera.width || depth_m.rows != depth_camera.height)
    throw Error(fmt::format("depth registration: depth image must be CV_32F {}x{}, got type {} {}x{}",
                            depth_camera.width, depth_camera.height, depth_m.type(), depth_m.cols, depth_m.rows));
  cv::Mat registered(colour_camera.height, colour_camera.width, CV_32F, cv::Scalar(0));
  for (int v = 0; v < depth_m.rows; ++v) {
    const float* row = depth_m.ptr<float>(v);
    for (int u = 0; u < depth_m.cols; ++u) {
      const double z = row[u];
      if (!(z > 0)) continue;
      const Vec3 p_depth((u - depth_camera.cx) * z / depth_camera.fx, (v - depth_camera.cy) * z / depth_camera.fy, z);
      const Vec3 p_colour = colour_from_depth * p_depth;
      if (p_colour.z() <= 0) continue;
      const long cu = std::lround(colour_camera.fx * p_colour.x() / p_colour.z() + colour_camera.cx);
      const long cv_row = std::lround(colour_camera.fy * p_colour.y() / p_colour.z() + colour_camera.cy);
      if (cu < 0 || cv_row < 0 || cu >= colour_camera.width || cv_row >= colour_camera.height) continue;
      float& target = registered.at<float>(static_cast<int>(cv_row), static_cast<int>(cu));
      const float depth = static_cast<float>(p_colour.z());
      if (target == 0 || depth < target) target = depth;  // nearest surface wins
    }
  }
  return registered;
}

}  // namespace esdslam
