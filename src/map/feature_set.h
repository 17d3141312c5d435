#pragma once
// The immutable per-image feature data that a Frame computes once and a KeyFrame keeps: keypoints,
// descriptors, per-keypoint depth, dynamic flags and a spatial grid. Shared by pointer between a
// Frame and the KeyFrame made from it. Immutable once shared (no lock is needed): only the Frame
// that owns it alone may still mark keypoints dynamic (Frame::MarkDynamic), during its tracking step.

#include <algorithm>
#include <cstdint>
#include <memory>
#include <vector>

#include <opencv2/core.hpp>

#include "common/geometry.h"
#include "feature/feature_grid.h"
#include "map/rgbd_rig.h"

namespace esdslam {

// FeatureSet::is_dynamic values (any nonzero value = dynamic).
constexpr std::uint8_t kDynamicByMask = 1;      // on the dynamic mask given with the image (semantics)
constexpr std::uint8_t kDynamicByGeometry = 2;  // found moving by the multi-view geometry check

// Whether a keypoint lies on `mask` (CV_8U over the raw image, nonzero = on): the mask pixel
// nearest its raw level-0 position, clamped to the image.
inline bool KeypointOnMask(const cv::KeyPoint& keypoint, const cv::Mat& mask) {
  const int u = std::clamp(cvRound(keypoint.pt.x), 0, mask.cols - 1);
  const int v = std::clamp(cvRound(keypoint.pt.y), 0, mask.rows - 1);
  return mask.at<std::uint8_t>(v, u) != 0;
}

struct FeatureSet {
  std::shared_ptr<const RgbdRig> rig;
  std::vector<cv::KeyPoint> keypoints;    // raw (distorted) level-0 px; octave = pyramid level
  std::vector<cv::Point2f> undistorted;   // undistorted px, same order
  cv::Mat descriptors;                    // N x 32 CV_8U
  std::vector<float> depth;               // metres along z at the raw keypoint; <= 0: no depth
  std::vector<float> right_u;             // virtual right u = u - bf / depth (px); < 0: none
  std::vector<std::uint8_t> is_dynamic;   // nonzero: on a moving object, never used for pose or map
  std::unique_ptr<FeatureGrid> grid;      // over `undistorted`

  int size() const { return static_cast<int>(keypoints.size()); }
  int level(int i) const { return keypoints[i].octave; }
  Vec2 pixel(int i) const { return {undistorted[i].x, undistorted[i].y}; }
  bool has_depth(int i) const { return depth[i] > 0; }
  bool is_close(int i) const { return depth[i] > 0 && depth[i] < rig->th_depth_m; }
  const unsigned char* descriptor(int i) const { return descriptors.ptr<unsigned char>(i); }
  // The keypoint back-projected with its depth, in the camera frame (m). Requires has_depth(i).
  Vec3 BackprojectCam(int i) const { return rig->camera.Backproject(pixel(i), depth[i]); }
};

}  // namespace esdslam
