#pragma once
// Turns a registered RGB-D frame into a coloured point cloud in the camera frame, leaving out
// dynamic pixels (mask dilated by DenseOptions::mask_dilation_px), invalid depth (0 or
// non-finite) and depth outside [min_depth, max_depth]. The depth image is registered to the raw
// (distorted) colour image; each pixel's ray is undistorted once and cached.
//
// It also keeps, per keyframe, the rays OctoMap needs to carve free space (KeyframeRays): the
// masked depth on a pixel grid coarse enough that neighbouring rays are about one OctoMap cell
// apart at the OctoMap range, as 16-bit millimetres. Depth beyond max_depth is kept there: such a
// reading still proves the space in front of it free.

#include <opencv2/core.hpp>

#include "camera/pinhole_camera.h"
#include "dense/dense_options.h"
#include "dense/point_cloud.h"

namespace esdslam {

struct KeyframeRays {
  int stride = 1;     // pixels between samples in u and v
  cv::Mat depth_mm;   // CV_16U; sample (r, c) is pixel (c * stride, r * stride); 0 = no ray
  std::size_t bytes() const { return depth_mm.total() * depth_mm.elemSize(); }
};

struct KeyframeObservation {
  PointCloud points_cam;  // every kept pixel (at pixel_stride), camera frame, not downsampled
  KeyframeRays rays;
};

class DepthBackprojector {
 public:
  DepthBackprojector(const PinholeCamera& camera, const DenseOptions& options);

  // bgr: CV_8UC3; depth_m: CV_32F metres; dynamic_mask: empty or CV_8U, nonzero = dynamic.
  // Points are in the camera frame (x right, y down, z forward).
  KeyframeObservation Observe(const cv::Mat& bgr, const cv::Mat& depth_m, const cv::Mat& dynamic_mask) const;
  PointCloud Backproject(const cv::Mat& bgr, const cv::Mat& depth_m, const cv::Mat& dynamic_mask) const {
    return Observe(bgr, depth_m, dynamic_mask).points_cam;
  }
  // Ray end points (camera frame) of the samples with depth.
  std::vector<Eigen::Vector3f> RayEndpoints(const KeyframeRays& rays) const;

  // The mask actually applied: `dynamic_mask` dilated (empty mask -> all zeros).
  cv::Mat ExclusionMask(const cv::Mat& dynamic_mask, cv::Size size) const;
  // CV_8U, 1 = valid pixel on the near side of a depth edge (DenseOptions::edge_filter_px, edge_jump_ratio).
  cv::Mat DepthEdges(const cv::Mat& depth_m) const;
  int ray_stride() const { return ray_stride_; }
  const PinholeCamera& camera() const { return camera_; }

 private:
  PointCloud BackprojectPixels(const cv::Mat& bgr, const cv::Mat& depth_m, const cv::Mat& excluded) const;
  KeyframeRays SampleRays(const cv::Mat& depth_m, const cv::Mat& excluded) const;
  Eigen::Vector3f Point(int u, int v, float z) const {
    return Eigen::Vector3f(ray_x_.at<float>(v, u) * z, ray_y_.at<float>(v, u) * z, z);
  }

  PinholeCamera camera_;
  DenseOptions options_;
  cv::Mat ray_x_, ray_y_;  // CV_32F: undistorted normalised coordinates (x/z, y/z) of each pixel
  int ray_stride_ = 1;
};

}  // namespace esdslam
