#pragma once
// Pinhole camera with radial-tangential (OpenCV / TUM) distortion k1 k2 p1 p2 k3.
// Pixel coordinates: (u, v) with u to the right, v down, origin at the centre of the top-left
// pixel. Camera frame: x right, y down, z forward, metres.

#include <algorithm>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "common/geometry.h"

namespace esdslam {

struct CameraIntrinsics {
  double fx = 0, fy = 0, cx = 0, cy = 0;
  double k1 = 0, k2 = 0, p1 = 0, p2 = 0, k3 = 0;
  int width = 640, height = 480;

  // Throws SettingError (common/error.h) naming the Camera.* key of a value out of its range.
  void Check() const;
  bool HasDistortion() const { return k1 != 0 || k2 != 0 || p1 != 0 || p2 != 0 || k3 != 0; }
  cv::Mat CameraMatrix() const;      // 3x3 CV_64F
  cv::Mat DistortionCoeffs() const;  // 1x5 CV_64F (k1 k2 p1 p2 k3)
};

class PinholeCamera {
 public:
  PinholeCamera() = default;
  explicit PinholeCamera(const CameraIntrinsics& intrinsics);

  const CameraIntrinsics& intrinsics() const { return intrinsics_; }
  double fx() const { return intrinsics_.fx; }
  double fy() const { return intrinsics_.fy; }
  double cx() const { return intrinsics_.cx; }
  double cy() const { return intrinsics_.cy; }
  int width() const { return intrinsics_.width; }
  int height() const { return intrinsics_.height; }

  // Ideal (undistorted) projection of a point in the camera frame. Requires z > 0.
  Vec2 Project(const Vec3& point_cam) const {
    return {fx() * point_cam.x() / point_cam.z() + cx(), fy() * point_cam.y() / point_cam.z() + cy()};
  }
  // Back-projects an undistorted pixel at depth z (metres, along the optical axis).
  Vec3 Backproject(const Vec2& pixel, double z) const {
    return {(pixel.x() - cx()) * z / fx(), (pixel.y() - cy()) * z / fy(), z};
  }
  // Applies the distortion model to an undistorted pixel (for drawing / synthetic data).
  Vec2 Distort(const Vec2& undistorted_pixel) const;
  // Removes distortion from raw pixel coordinates (iterative, as cv::undistortPoints).
  std::vector<cv::Point2f> Undistort(const std::vector<cv::Point2f>& raw_pixels) const;

  // Whether an undistorted pixel lies within the image bounds of the undistorted image.
  bool InImage(const Vec2& pixel) const {
    return pixel.x() >= min_u_ && pixel.x() < max_u_ && pixel.y() >= min_v_ && pixel.y() < max_v_;
  }
  double min_u() const { return min_u_; }
  double max_u() const { return max_u_; }
  double min_v() const { return min_v_; }
  double max_v() const { return max_v_; }

 private:
  CameraIntrinsics intrinsics_;
  // Bounds of the image corners after undistortion (equal to the image size without distortion).
  double min_u_ = 0, max_u_ = 0, min_v_ = 0, max_v_ = 0;
};

// Rolling shutter: seconds from the middle row's exposure to that of image row `row` (px, rows
// read top to bottom, readout_s from the first row to the last of an image `height` rows high).
// The one convention of the tracker's correction (RgbdRig::readout_time_s) and the synthetic
// renderer (SynthOptions::readout_time_s).
inline double RowTimeOffset(double row, int height, double readout_s) {
  return (row / std::max(1, height - 1) - 0.5) * readout_s;
}

}  // namespace esdslam
