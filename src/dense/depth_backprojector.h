#pragma once
// Turns a registered RGB-D frame into a coloured point cloud in the camera frame, leaving out
// dynamic pixels (mask dilated by DenseOptions::mask_dilation_px), invalid depth (0 or
// non-finite) and depth outside [min_depth, max_depth]. The depth image is registered to the raw
// (distorted) colour image; each pixel's ray is undistorted once and cached.

#include <opencv2/core.hpp>

#include "camera/pinhole_camera.h"
#include "dense/dense_options.h"
#include "dense/point_cloud.h"

namespace esdslam {

class DepthBackprojector {
 public:
  DepthBackprojector(const PinholeCamera& camera, const DenseOptions& options);

  // bgr: CV_8UC3; depth_m: CV_32F metres; dynamic_mask: empty or CV_8U, nonzero = dynamic.
  // Output points are in the camera frame (x right, y down, z forward), downsampled to the
  // voxel size.
  PointCloud Backproject(const cv::Mat& bgr, const cv::Mat& depth_m, const cv::Mat& dynamic_mask) const;

  // The mask actually applied: `dynamic_mask` dilated (empty mask -> all zeros).
  cv::Mat ExclusionMask(const cv::Mat& dynamic_mask, cv::Size size) const;

 private:
  PinholeCamera camera_;
  DenseOptions options_;
  cv::Mat ray_x_, ray_y_;  // CV_32F: undistorted normalised coordinates (x/z, y/z) of each pixel
};

}  // namespace esdslam
