#pragma once
// RGB-D tracking (ORB-SLAM2's Tracking, RGB-D path), run on the caller's thread:
//   initialisation from the first frame with enough depth; constant-velocity motion model with
//   projection search from the last frame (plus temporary depth points of the last frame);
//   reference-keyframe matching as fallback; local-map tracking (covisible keyframes, projection
//   search, motion-only BA); keyframe decision and creation (with close points from depth).
// While LOST the tracker keeps trying to match the last reference keyframe's local map; frames
// without a pose get none (no pose is invented).
//
// Locking: Track() holds Map::update_mutex() for the whole step; new keyframes are handed to the
// KeyFrameSink after the lock is released. Poses carried between frames (last frame, last tracked
// pose) are kept relative to their reference keyframes, so they follow map corrections (local BA,
// loop closing, global BA); the motion model is a relative motion and needs no correction.

#include <memory>
#include <optional>
#include <unordered_set>
#include <vector>

#include "map/keyframe_sink.h"
#include "map/map.h"
#include "optim/pose_optimizer.h"
#include "tracking/depth_alignment.h"
#include "tracking/frame.h"

namespace esdslam {

class Relocalizer;           // tracking/relocalizer.h
class MovingKeypointFilter;  // tracking/moving_keypoint_filter.h

enum class TrackingState { kNotInitialized, kOk, kLost };
const char* ToString(TrackingState state);

struct TrackerOptions {
  int min_initial_depth_keypoints = 500;  // keypoints with depth needed to initialise the map
  int max_frames_between_keyframes = 30;  // ORB-SLAM2: fps
  int min_frames_between_keyframes = 0;
  double motion_search_radius_px = 15;    // projection window from the last frame (doubled on failure)
  double local_search_radius_factor = 3;  // ORB-SLAM2 RGB-D: th = 3
  int min_motion_matches = 20;            // projection matches needed before pose optimisation
  int min_pose_matches = 10;              // map matches left after optimisation
  int min_local_map_inliers = 30;         // tracking is LOST below this
  int max_local_keyframes = 80;
  bool last_frame_depth_points = true;    // temporary points from the last frame's close depth
  int max_depth_points = 100;             // close points per keyframe / temporary points
  bool localization_only = false;         // never insert keyframes (tracking in a fixed, loaded map)
  // For max_frames_between_keyframes frames (1 s) after a BoW relocalization the relocalized pose
  // rests on the few old points in view: tracking needs this many local-map inliers (ORB-SLAM2:
  // 50) and creates no keyframe (ORB-SLAM2 exempts maps with <= 1 s of keyframes; we do not:
  // keyframes made at once bake the relocalization error into a new sub-map that later fails to
  // re-match the old one). The local-map window is widened to this factor for 2 frames (ORB-SLAM2: 5).
  int relocalized_min_inliers = 50;
  double relocalized_search_radius_factor = 5;
  // A blind frame (fewer than min_local_map_inliers static keypoints: a blocked or dark sensor, a
  // person filling the view) cannot be tracked. While tracking was OK, such a frame gets the
  // motion model's pose (constant velocity from the last tracked frames) instead of none, for
  // at most this many frames in a row (0 = off); no keyframe is made from it, and the next frame
  // is tracked as after any failed motion-model step (reference keyframe, then relocalization).
  int max_coasted_frames = 5;
  // Motion prior (issue 13), off by default: when local-map tracking has fewer than
  // motion_prior_below_matches matches, its pose optimisation gets a Gaussian prior at the
  // constant-velocity prediction, with sigmas learnt from how far the tracked poses of
  // well-matched frames fell from their predictions (a running mean over about 20 frames, at
  // least motion_prior_min_sigma_*). Few matches are often clustered on the static strip people
  // leave: the prior holds the directions they leave weak. It helps where the motion is smooth
  // (synthetic occlusion preset, docs/RESULTS.md) and hurts where the prediction is wrong (a
  // frame lost in a run whose movers are not masked), so it is not on by default. 0 = off.
  int motion_prior_below_matches = 0;
  double motion_prior_min_sigma_m = 0.002;
  double motion_prior_min_sigma_rad = 0.002;
  // Depth prior (issue 13): local-map pose optimisation gets a Gaussian prior at the pose that
  // aligns the frame's static depth to the previous frame's (point-to-plane,
  // tracking/depth_alignment.h), with that alignment's information matrix times
  // depth_prior_weight; it replaces the motion prior where both would apply. Only while tracking
  // is OK with a motion model. Measured in docs/RESULTS.md ("Depth prior").
  bool depth_prior = true;
  double depth_prior_weight = 0.01;  // (0, 1]: each depth sample's share of an independent reading (see DepthPrior)
  DepthAlignmentOptions depth_alignment;
  PoseOptimizerOptions pose;
  void Check() const;
};

// Per-step outcome, for logging and timing.
struct TrackingResult {
  TrackingState state = TrackingState::kNotInitialized;
  bool has_pose = false;
  Rigid3 cam_from_world;
  KeyFrame* reference_keyframe = nullptr;  // for has_pose: pose stored relative to it
  KeyFrame* new_keyframe = nullptr;        // created in this step (already handed to the sink)
  int inliers = 0;
  bool coasted = false;  // blind frame: the pose is the motion model's prediction (max_coasted_frames)
};

class Tracker {
 public:
  // `sink` may be null (no local mapping: keyframes are only added to the map).
  Tracker(Map* map, KeyFrameSink* sink, const TrackerOptions& options);

  // Tracks the frame (sets its pose, associations, reference keyframe). `moving_filter` (null =
  // none; not owned, used during this call only) is the check run between the first pose and
  // local-map tracking: keypoints it finds moving are dropped and the pose is re-estimated
  // without them; it also sees the keyframe made from this frame, if any.
  TrackingResult Track(Frame* frame, MovingKeypointFilter* moving_filter = nullptr);

  TrackingState state() const { return state_; }
  // Global BoW relocalization tried while LOST when the reference-keyframe retry fails (null = off;
  // not owned). Tracking resumes in the same map.
  void set_relocalizer(Relocalizer* relocalizer) { relocalizer_ = relocalizer; }
  // For a map loaded from a file: start LOST, so the first frames are relocalized in it.
  void StartInExistingMap() { state_ = TrackingState::kLost; }
  // Frames relocalized by the relocalizer so far.
  int relocalizations() const { return relocalizations_; }
  const Frame& last_frame() const { return last_frame_; }
  const std::vector<KeyFrame*>& local_keyframes() const { return local_keyframes_; }
  const std::vector<MapPoint*>& local_points() const { return local_points_; }

 private:
  // Steps (tracker.cpp).
  bool Initialize(Frame* frame);
  bool TrackWithMotionModel(Frame* frame);
  bool TrackReferenceKeyFrame(Frame* frame);
  bool Relocalize(Frame* frame);  // tracker_relocalization.cpp
  void UpdateLastFrame();
  void FilterMovingKeypoints(Frame* frame, MovingKeypointFilter* filter);
  void ReplaceMovedPointsInLastFrame();
  int DiscardOutliers(Frame* frame);
  bool Coast(Frame* frame);
  std::optional<PosePrior> MotionPrior(int matches) const;
  std::optional<PosePrior> DepthPrior(const Frame& frame);
  void LearnPredictionError(const Frame& frame);
  void Finish(Frame* frame, bool tracked);
  // Local map (tracker_local_map.cpp).
  bool TrackLocalMap(Frame* frame);
  void UpdateLocalKeyFrames(Frame* frame);
  void UpdateLocalPoints();
  void SearchLocalPoints(Frame* frame);
  bool NeedNewKeyFrame(const Frame& frame) const;
  // Within max_frames_between_keyframes frames after a relocalization (frame ids).
  bool RecentlyRelocalized(const Frame& frame, long frames) const {
    return last_relocalization_frame_id_ >= 0 && frame.id() < last_relocalization_frame_id_ + frames;
  }
  KeyFrame* CreateNewKeyFrame(Frame* frame);
  MapPoint* CreatePointFromDepth(KeyFrame* keyframe, const Frame& frame, int index);

  Map* map_;
  KeyFrameSink* sink_;
  TrackerOptions options_;

  TrackingState state_ = TrackingState::kNotInitialized;
  Frame last_frame_;
  Rigid3 last_cam_from_reference_;  // last_frame_'s pose relative to its reference keyframe
  bool velocity_valid_ = false;
  Rigid3 velocity_;  // current cam_from_last cam
  double velocity_interval_s_ = 0;  // the time between the two frames velocity_ was measured on
  KeyFrame* last_good_reference_ = nullptr;  // the last tracked frame's reference (null: none yet)
  Rigid3 last_good_cam_from_reference_;
  KeyFrame* reference_keyframe_ = nullptr;
  KeyFrame* last_keyframe_ = nullptr;
  long last_keyframe_frame_id_ = -1;
  long last_relocalization_frame_id_ = -1;  // -1: none
  int inliers_ = 0;
  int coasted_frames_ = 0;  // blind frames in a row given the motion model's pose (Coast)
  std::unique_ptr<DepthAligner> depth_aligner_;  // the depth prior's, made for the first frame's camera
  // The constant-velocity prediction of the frame being tracked (valid during Track when tracking
  // was OK with a velocity), and the running mean squared prediction errors (translation m^2,
  // rotation rad^2, norms over the 3 axes) of well-matched frames.
  std::optional<Rigid3> predicted_cam_from_world_;
  double prediction_error_t2_ = 0, prediction_error_r2_ = 0;
  int prediction_error_samples_ = 0;
  std::vector<KeyFrame*> local_keyframes_;
  std::vector<MapPoint*> local_points_;
  std::vector<std::unique_ptr<MapPoint>> temporary_points_;  // depth points of the last frame
  // During one Track() call: points matched in the frame when local-map search starts or dropped
  // as outliers earlier in the call; local-map search does not project them again. Empty between calls.
  std::unordered_set<const MapPoint*> seen_this_frame_;
  Relocalizer* relocalizer_ = nullptr;
  int relocalizations_ = 0;
};

}  // namespace esdslam
