#include "camera/pinhole_camera.h"

#include <algorithm>

#include <opencv2/calib3d.hpp>

#include "common/error.h"
#include "common/setting_error.h"

namespace esdslam {

void CameraIntrinsics::Check() const {
  CheckRange("Camera.width", width, 8, 20000, "px");
  CheckRange("Camera.height", height, 8, 20000, "px");
  CheckRange("Camera.fx", fx, 1.0, 1e6, "px");
  CheckRange("Camera.fy", fy, 1.0, 1e6, "px");
  // The principal point may lie off the image (cropped sensors), but not far off.
  CheckRange("Camera.cx", cx, -1.0 * width, 2.0 * width, "px");
  CheckRange("Camera.cy", cy, -1.0 * height, 2.0 * height, "px");
  const std::pair<const char*, double> coefficients[] = {{"Camera.k1", k1}, {"Camera.k2", k2}, {"Camera.p1", p1},
                                                         {"Camera.p2", p2}, {"Camera.k3", k3}};
  for (const auto& [key, value] : coefficients) CheckRange(key, value, -1000.0, 1000.0);
}

cv::Mat CameraIntrinsics::CameraMatrix() const {
  return (cv::Mat_<double>(3, 3) << fx, 0, cx, 0, fy, cy, 0, 0, 1);
}

cv::Mat CameraIntrinsics::DistortionCoeffs() const {
  return (cv::Mat_<double>(1, 5) << k1, k2, p1, p2, k3);
}

PinholeCamera::PinholeCamera(const CameraIntrinsics& intrinsics) : intrinsics_(intrinsics) {
  intrinsics_.Check();
  if (!intrinsics_.HasDistortion()) {
    min_u_ = 0;
    min_v_ = 0;
    max_u_ = intrinsics_.width;
    max_v_ = intrinsics_.height;
    return;
  }
  const float w = static_cast<float>(intrinsics_.width);
  const float h = static_cast<float>(intrinsics_.height);
  const auto corners = Undistort({{0.f, 0.f}, {w, 0.f}, {0.f, h}, {w, h}});
  min_u_ = std::min(corners[0].x, corners[2].x);
  max_u_ = std::max(corners[1].x, corners[3].x);
  min_v_ = std::min(corners[0].y, corners[1].y);
  max_v_ = std::max(corners[2].y, corners[3].y);
}

Vec2 PinholeCamera::Distort(const Vec2& undistorted_pixel) const {
  const auto& k = intrinsics_;
  const double x = (undistorted_pixel.x() - k.cx) / k.fx;
  const double y = (undistorted_pixel.y() - k.cy) / k.fy;
  const double r2 = x * x + y * y;
  const double radial = 1 + k.k1 * r2 + k.k2 * r2 * r2 + k.k3 * r2 * r2 * r2;
  const double xd = x * radial + 2 * k.p1 * x * y + k.p2 * (r2 + 2 * x * x);
  const double yd = y * radial + k.p1 * (r2 + 2 * y * y) + 2 * k.p2 * x * y;
  return {k.fx * xd + k.cx, k.fy * yd + k.cy};
}

std::vector<cv::Point2f> PinholeCamera::Undistort(const std::vector<cv::Point2f>& raw_pixels) const {
  if (raw_pixels.empty() || !intrinsics_.HasDistortion()) return raw_pixels;
  std::vector<cv::Point2f> out;
  const cv::Mat k = intrinsics_.CameraMatrix();
  cv::undistortPoints(raw_pixels, out, k, intrinsics_.DistortionCoeffs(), cv::noArray(), k);
  return out;
}

}  // namespace esdslam
