#pragma once
// The multi-view geometry check inside tracking (ESD-SLAM Algorithm 2, after DynaSLAM). It runs
// once the frame has a first pose from the semantically filtered features and before local-map
// tracking:
//   1. reference keyframes: the (up to 5) live keyframes that observe the most map points
//      matched in the frame (covisibility with the frame);
//   2. their keypoints with depth (not dynamic), lifted to the world with the keyframes' current
//      poses, are checked against the frame's depth image (dynamic/geometry_check.h). The
//      keyframe's own measurement, not the map point's position, is compared: the check asks
//      what changed since that keyframe was taken, and a map point's position blends views from
//      different times (and most keypoints with depth have no map point); the difference for
//      static points, the depth noise, is far below the threshold. The
//      keyframes' depth images kept here (reduced, bounded: dynamic/keyframe_depth_store.h) veto
//      occlusions caused by the viewpoint change;
//   3. keypoints on the mask grown from the flags (outside Frame::geometry_exempt: trusted static
//      classes and the semantic mask) become dynamic (kDynamicByGeometry): they lose their
//      association, take no part in pose estimation and never create map points;
//   4. map points are voted on (dynamic/moving_point_votes.h): evidence when the frame sees
//      through them (via a reference keyframe keypoint observing them) or when they were matched
//      to a keypoint found moving; a consistent depth resets; points with evidence in
//      cull_after_frames consecutive tested frames are culled (MapPoint::SetBad).
// Threading: called by the tracker while it holds Map::update_mutex (culling is a structure
// change under the map lock, docs/CORE.md). Owned by the tracking thread; not thread-safe.

#include <unordered_map>
#include <vector>

#include <opencv2/core.hpp>

#include "dynamic/geometry_check.h"
#include "dynamic/keyframe_depth_store.h"
#include "dynamic/moving_point_votes.h"
#include "common/geometry.h"
#include "map/map_types.h"
#include "tracking/moving_keypoint_filter.h"

namespace esdslam {

class Frame;

struct GeometryFilterOptions {
  GeometryCheckOptions check;
  int reference_keyframes = 5;        // keyframes sharing the most map points with the frame
  // Only keyframes at least this much older than the frame (s) are references, when any such
  // keyframe shares points: a mover must have had time to move (1 m/s walking: 25 cm in 0.25 s),
  // and a keyframe taken while the pose drifted with a mover cannot vouch for it. 0 = any age.
  double min_reference_age_s = 0.25;
  int keyframe_depth_capacity = 100;  // keyframe depth images kept for the veto (0 = points only)
  double keyframe_depth_scale = 0.5;  // ... at this scale (0.5: 0.3 MB per VGA keyframe)
  int cull_after_frames = 3;          // consecutive tested frames with evidence before culling (0 = never cull)
  void Check() const;                 // throws Error
};

struct GeometryFilterStats {
  bool ran = false;           // the check ran on this frame (it had a pose and reference keyframes)
  double check_ms = 0;        // selection, check, flagging, voting and culling (wall time)
  double check_cpu_ms = 0;    // the same, CPU time of the tracking thread
  int reference_keyframes = 0;
  int tested = 0, covered = 0, vanished = 0;  // reference points (GeometryCheckResult)
  double image_motion_px = 0;  // since the previous frame (from the poses), sizes the depth window
  int window_radius_px = 0;
  bool skipped_fast_motion = false;
  std::vector<int> flagged_keypoints;  // found moving, ascending (the tracker marks them kDynamicByGeometry)
  int associations_removed = 0;
  int points_culled = 0;
  std::vector<Vec3> culled_positions;  // world positions (m) of the points culled (a viewer shows them)
  cv::Mat mask;               // CV_8U, 255 = moving by geometry; empty when the check did not run
};

class GeometryFilter {
 public:
  explicit GeometryFilter(const GeometryFilterOptions& options);

  // frame: tracked with a first pose and map point associations; caller holds Map::update_mutex.
  // Finds the moving keypoints (`flagged_keypoints`; the frame is not changed) and culls moved points;
  // returns what it found and did on this frame (associations_removed > 0: the caller
  // re-estimates the pose).
  GeometryFilterStats Apply(const Frame& frame);
  // A keyframe just made from `frame`: keeps its depth image for the veto.
  void AddKeyFrame(const KeyFrame& keyframe, const Frame& frame);

  long total_points_culled() const { return total_culled_; }
  const GeometryFilterOptions& options() const { return options_; }

 private:
  struct Flagged {
    std::vector<int> keypoints;
    int associations_removed = 0;
  };
  std::vector<KeyFrame*> SelectKeyFrames(const Frame& frame) const;
  double ImageMotionSinceLastFrame(const Frame& frame) const;
  // Reference points of each keyframe and the keypoint each came from.
  std::vector<ReferenceKeyframe> BuildReferences(const std::vector<KeyFrame*>& keyframes,
                                                 std::vector<std::vector<int>>* keypoints);
  Flagged FlagKeypoints(const Frame& frame, const cv::Mat& mask);
  void VoteReferencePoints(const std::vector<KeyFrame*>& keyframes, const std::vector<std::vector<int>>& keypoints,
                           const GeometryCheckResult& result);
  // Returns the points culled; their world positions are appended to *positions.
  int CullMovedPoints(std::vector<Vec3>* positions);
  void Evidence(MapPoint* point);

  GeometryFilterOptions options_;
  KeyframeDepthStore depths_;
  std::unordered_map<long, const KeyFrame*> depth_owners_;  // keyframes with a stored depth
  MovingPointVotes votes_;
  std::unordered_map<long, MapPoint*> evidence_points_;  // this frame's evidence, by point id
  long total_culled_ = 0;
  long last_frame_id_ = -1;  // last frame checked, and its pose
  Rigid3 last_cam_from_world_;
};

// The filter plugged into one Tracker::Track call (tracking's MovingKeypointFilter hook, which
// returns only what tracking applies): keeps the statistics GeometryFilter::Apply returned for
// that call. Make one per frame; stats() is all zero when tracking did not reach the check.
class GeometryFilterHook final : public MovingKeypointFilter {
 public:
  explicit GeometryFilterHook(GeometryFilter* filter) : filter_(filter) {}
  MovingKeypoints FindMoving(const Frame& frame) override;
  void AddKeyFrame(const KeyFrame& keyframe, const Frame& frame) override { filter_->AddKeyFrame(keyframe, frame); }
  const GeometryFilterStats& stats() const { return stats_; }

 private:
  GeometryFilter* filter_;  // not owned
  GeometryFilterStats stats_;
};

}  // namespace esdslam
