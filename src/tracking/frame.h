#pragma once
// One RGB-D image prepared for tracking: ORB features (shared, immutable FeatureSet), per-keypoint
// map point associations and outlier flags, and the pose once tracked.
//
// Dynamic-object hook: `dynamic_mask` (CV_8U, nonzero = on a moving object, same size as the
// image) flags the keypoints on it (FeatureSet::is_dynamic); flagged keypoints are never matched
// for pose estimation nor turned into map points. With `FrameOptions::mask_extraction` the ORB
// budget is spent on the static area only.

#include <memory>
#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "feature/orb_extractor.h"
#include "map/feature_set.h"
#include "map/map_types.h"

namespace esdslam {

struct FrameOptions {
  bool mask_extraction = false;  // pass the complement of the dynamic mask to the extractor
  bool image_is_rgb = false;     // colour channel order of the input (false: OpenCV BGR)
  bool pyramid_centre_correction = true;  // see CorrectPyramidOffsets in frame.cpp
};

// The shared constants of a run: camera, bf, close-depth threshold (th_depth * bf / fx metres,
// as ORB-SLAM2's ThDepth) and the extractor's scale pyramid.
std::shared_ptr<const RgbdRig> MakeRgbdRig(const CameraIntrinsics& intrinsics, double bf, double th_depth,
                                           const OrbExtractor& extractor, double readout_time_s = 0.0);

// Where a map point falls in a frame (see Frame::ProjectInFrustum); pixels undistorted.
struct PointProjection {
  MapPoint* point = nullptr;
  double u = 0, v = 0;     // projection (px)
  double right_u = 0;      // virtual right-camera u = u - bf / z (px)
  int predicted_level = 0; // pyramid level predicted from the distance
  double view_cos = 0;     // cos of the angle between the viewing ray and the point's mean normal
};

class Frame {
 public:
  Frame() = default;
  // image: CV_8UC3 colour or CV_8UC1 grey. depth_m: CV_32F metres (0 = invalid), same size.
  // Throws Error on empty or mismatched images.
  Frame(long id, double timestamp, const cv::Mat& image, const cv::Mat& depth_m, const cv::Mat& dynamic_mask,
        const OrbExtractor& extractor, std::shared_ptr<const RgbdRig> rig, const FrameOptions& options = {});

  long id() const { return id_; }
  double timestamp() const { return timestamp_; }
  const FeatureSet& features() const { return *features_; }
  std::shared_ptr<const FeatureSet> shared_features() const { return features_; }
  const RgbdRig& rig() const { return *features_->rig; }
  int size() const { return features_ ? features_->size() : 0; }
  bool valid() const { return features_ != nullptr; }

  // Associations (index = keypoint index).
  std::vector<MapPoint*> map_points;
  std::vector<bool> outlier;

  bool has_pose = false;
  Rigid3 cam_from_world;  // valid when has_pose
  Vec3 camera_center() const { return cam_from_world.inverse().translation(); }
  KeyFrame* reference_keyframe = nullptr;

  // Projects a map point with the current pose; returns the projection when it is in front of
  // the camera, inside the image, within the point's scale-invariance distance range and seen at
  // an angle with cos >= min_view_cos to its mean viewing direction, else nothing.
  std::optional<PointProjection> ProjectInFrustum(MapPoint* point, double min_view_cos) const;
  // Rolling shutter (rig().readout_time_s > 0; else nothing happens): moves each keypoint's
  // undistorted position, depth and virtual right u to where it would be seen at the middle row's time,
  // for a camera turning at `angular_velocity_cam` (rad/s, in the camera frame: a static point's
  // camera coordinates change as X(t + dt) = exp([w]x dt) X(t)). Always starts from the positions
  // as extracted, so a second call replaces the first one's correction. Only while no keyframe
  // shares the features; throws Error otherwise.
  void CompensateRollingShutter(const Vec3& angular_velocity_cam);
  // Keypoint count with depth.
  int NumWithDepth() const;
  // Clears the associations to map points set bad (culled) since they were made.
  void DropBadAssociations();

  // The depth image the frame was built from (CV_32F metres, raw pixel grid; shared, not copied).
  const cv::Mat& depth_m() const { return depth_m_; }
  // The dynamic mask the frame was built with (CV_8U, nonzero = dynamic; shared, not copied;
  // empty = none).
  const cv::Mat& dynamic_mask() const { return dynamic_mask_; }
  // Flags keypoint i dynamic (reason: kDynamicByMask or kDynamicByGeometry) and drops its
  // association. Only while no keyframe shares the features yet; throws Error otherwise.
  void MarkDynamic(int i, std::uint8_t reason);

  // Regions the multi-view geometry check leaves alone (CV_8U, nonzero = exempt: trusted static
  // classes, pixels already on the dynamic mask); empty = none.
  cv::Mat geometry_exempt;

 private:
  long id_ = -1;
  double timestamp_ = 0;
  std::shared_ptr<FeatureSet> features_;  // shared with keyframes as const (see MarkDynamic)
  // Undistorted keypoint positions as extracted, before any rolling-shutter correction (empty
  // until the first CompensateRollingShutter call).
  std::vector<cv::Point2f> extracted_undistorted_;
  std::vector<float> extracted_depth_;  // FeatureSet::depth as extracted, same rule
  cv::Mat depth_m_;
  cv::Mat dynamic_mask_;
};

}  // namespace esdslam
