#pragma once
// Free-space evidence from one depth image: does the frame see a stored surface point where the
// map holds it, see past it (the space is empty), or not see it at all?
//
// A world point is projected into the frame (pinhole with the camera's distortion, nearest
// sample of a depth image taken every `stride` pixels). With z its depth along the optical axis,
// d the measured depth there and margin(d) = max(min_margin, sigmas * sigma(d)) + extent,
// sigma(d) = depth_noise_at_1m * d^2 the sensor's depth noise and `extent` the half size of what
// is tested (0 for a point, half a cell diagonal for an OctoMap cell):
//   kSeen     |d - z| <= margin(d)
//   kFree     the frame saw beyond the point: d_min > z + margin(d), where d_min is the smallest
//             valid depth in a (2 * window + 1)^2 neighbourhood of the sample (every neighbour
//             must be valid). A point at a depth edge that a pose error of a few pixels puts over
//             the background is not carved: one foreground neighbour suffices to keep it.
//   kUnknown  outside the image, behind the camera, no valid depth, or occluded (d < z - margin).
//
// Evidence per stored element (point or cell): +1 for kSeen up to max_evidence, -1 for kFree; an
// element whose evidence reaches 0 after a kFree is removed. So a surface seen by many frames needs
// max_evidence frames that see through it (a chair pushed away, a door opened), while a reading
// seen once (a person's foot outside the mask, a flying pixel) goes with the first frame that
// sees past it.

#include <cstdint>

#include <opencv2/core.hpp>

#include "camera/pinhole_camera.h"
#include "dense/dense_options.h"

namespace esdslam {

enum class FreeSpaceVerdict : std::uint8_t { kUnknown, kSeen, kFree };

class FreeSpaceView {
 public:
  // depth_m: CV_32F metres (0 = invalid), sample (r, c) = raw pixel (c * stride, r * stride).
  FreeSpaceView(const PinholeCamera& camera, const Rigid3& world_from_cam, const cv::Mat& depth_m, int stride,
                const DenseOptions& options);

  FreeSpaceVerdict Classify(const Eigen::Vector3f& p_world, float extent = 0.0f) const {
    return ClassifyInCamera(rotation_ * p_world + translation_, extent);
  }
  // The same for a point already in this view's camera frame (callers that move many points of
  // one frame compose the transforms once).
  FreeSpaceVerdict ClassifyInCamera(const Eigen::Vector3f& p_cam, float extent = 0.0f) const;
  const Eigen::Matrix3f& cam_from_world_rotation() const { return rotation_; }
  const Eigen::Vector3f& cam_from_world_translation() const { return translation_; }

 private:
  float Margin(float depth) const;

  CameraIntrinsics intrinsics_;
  bool distorted_ = false;
  Eigen::Matrix3f rotation_;  // cam_from_world
  Eigen::Vector3f translation_;
  cv::Mat depth_;      // CV_32F
  cv::Mat min_depth_;  // CV_32F: neighbourhood minimum, 0 where any neighbour is invalid
  float inv_stride_ = 1;
  float noise_at_1m_ = 0, sigmas_ = 3, min_margin_ = 0;
};

// Evidence update of one element, as described above. Returns false when the element is to be removed.
inline bool UpdateEvidence(FreeSpaceVerdict verdict, int max_evidence, std::uint8_t* evidence) {
  if (verdict == FreeSpaceVerdict::kSeen) {
    if (*evidence < max_evidence) ++*evidence;
  } else if (verdict == FreeSpaceVerdict::kFree) {
    if (*evidence > 0) --*evidence;
    return *evidence > 0;
  }
  return true;
}

}  // namespace esdslam
