#pragma once
// The SLAM system: owns the map, the ORB extractor, the tracker (run on the caller's thread by
// TrackRgbd), the local-mapping thread and the loop-closing thread (with its global-BA thread);
// in single-thread mode local mapping and loop closing (global BA included) run on the caller's
// thread right after each tracking step, which makes runs exactly repeatable.
// Hand-offs: tracking -> (BoW indexing) -> local mapping -> loop closing (docs/CORE.md).
//
// Trajectory: every tracked frame is stored relative to its reference keyframe (ORB-SLAM2), so
// the output reflects later keyframe corrections by BA; world = the first keyframe's camera.

#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "feature/orb_extractor.h"
#include "io/settings.h"
#include "io/trajectory_io.h"
#include "map/map.h"
#include "map/map_serialization.h"
#include "mapping/local_mapper.h"
#include "system/loop_settings.h"
#include "system/place_indexing_sink.h"
#include "dynamic/geometry_filter.h"
#include "tracking/relocalizer.h"
#include "tracking/tracker.h"

namespace esdslam {

struct SlamOptions {
  bool single_thread = false;  // local mapping on the caller's thread (deterministic)
  TrackerOptions tracker;      // a run sets max_frames_between_keyframes from Camera.fps (system/run_config.h)
  LocalMapperOptions mapping;
  FrameOptions frame;
  LoopOptions loop;            // place recognition, relocalization, loop closing (system/loop_settings.h)
  bool geometry_check = false; // multi-view geometry check in tracking (dynamic/geometry_filter.h)
  GeometryFilterOptions geometry;
  // Map file to start from (map/map_serialization.h): tracking starts LOST and relocalizes in it.
  // With tracker.localization_only no keyframe is added (needs loop.relocalization).
  std::string load_map;
  void Check() const;
};

struct TrackOutcome {
  TrackingState state = TrackingState::kNotInitialized;
  bool has_pose = false;
  Rigid3 world_from_cam;  // valid when has_pose
  bool new_keyframe = false;
  KeyFrame* keyframe = nullptr;  // the new keyframe when new_keyframe (owned by the map, never freed before it)
  int inliers = 0;
  bool coasted = false;  // a blind frame given the motion model's pose (TrackerOptions::max_coasted_frames)
  double extract_ms = 0;  // Frame construction (ORB extraction, undistortion, depth lookup)
  double track_ms = 0;    // tracking step, plus local mapping in single-thread mode
  // The geometry check inside the tracking step (part of track_ms), as GeometryFilter::Apply
  // returned it; all zero (ran = false) when it is off or tracking did not reach it.
  GeometryFilterStats geometry;
};

class SlamSystem {
 public:
  // Takes both as they are (checked, never changed). Throws Error on a failed check.
  SlamSystem(const Settings& settings, const SlamOptions& options);
  ~SlamSystem();
  SlamSystem(const SlamSystem&) = delete;
  SlamSystem& operator=(const SlamSystem&) = delete;

  // bgr: CV_8UC3 (or CV_8UC1 grey); depth_m: CV_32F metres, 0 = invalid; dynamic_mask: empty or
  // CV_8U, nonzero = moving object; geometry_exempt: empty or CV_8U, nonzero = left alone by the
  // geometry check (Frame::geometry_exempt). Throws Error on bad images, after Shutdown() or when
  // local mapping or loop closing failed.
  TrackOutcome TrackRgbd(const cv::Mat& bgr, const cv::Mat& depth_m, double timestamp,
                         const cv::Mat& dynamic_mask = cv::Mat(), const cv::Mat& geometry_exempt = cv::Mat());

  // For a keyframe whose dynamic mask came only after it was made: its keypoints on `mask`
  // (CV_8U of the image's size, nonzero = dynamic; raw pixel coordinates, as TrackRgbd's
  // dynamic_mask) become dynamic (KeyFrame::MarkLateDynamic: never given a point again) and the
  // live map points it observes there are removed (MapPoint::SetBad). Returns how many points;
  // 0 for a bad keyframe or an empty mask. Under the map's update lock (tracking thread).
  int RemovePointsUnder(KeyFrame* keyframe, const cv::Mat& mask);
  // Finishes local mapping, then loop closing (processes queued keyframes, waits for a running
  // global BA) and joins their threads. Idempotent. Throws Error when a worker failed.
  void Shutdown();
  // Writes the live keyframes and points (call after Shutdown for the final map). Throws Error.
  MapFileSummary SaveMap(const std::string& path);

  // world_from_cam of every frame that got a pose, in input order.
  std::vector<StampedPose> Trajectory() const;
  // world_from_cam of the live keyframes, by id.
  std::vector<StampedPose> KeyFrameTrajectory() const;

  const SlamOptions& options() const { return options_; }
  TrackingState state() const { return tracker_->state(); }
  int num_keyframes() const { return map_->num_keyframes(); }
  int num_map_points() const { return map_->num_map_points(); }
  int frames_seen() const { return static_cast<int>(next_frame_id_); }
  LocalMapperStats mapping_stats() const { return mapper_->stats(); }
  int relocalizations() const { return tracker_->relocalizations(); }
  // Empty (all zero) when loop closing is off.
  LoopClosingStats loop_stats() const;
  // Null when relocalization and loop closing are disabled.
  PlaceRecognition* place_recognition() { return places_.get(); }
  Map& map() { return *map_; }
  // The frame of the last TrackRgbd call (keypoints, is_dynamic flags, associations).
  const Frame& last_frame() const { return tracker_->last_frame(); }
  const std::shared_ptr<const RgbdRig>& rig() const { return rig_; }

 private:
  struct FrameRecord {
    double timestamp;
    KeyFrame* reference;  // nullptr: no pose
    Rigid3 cam_from_reference;
  };

  const Settings settings_;
  const SlamOptions options_;
  std::unique_ptr<OrbExtractor> extractor_;
  std::shared_ptr<const RgbdRig> rig_;
  std::unique_ptr<Map> map_;
  std::unique_ptr<LocalMapper> mapper_;
  std::unique_ptr<PlaceRecognition> places_;          // null without relocalization and loop closing
  std::unique_ptr<PlaceIndexingSink> indexing_sink_;  // tracking -> (BoW indexing) -> local mapping
  std::unique_ptr<Relocalizer> relocalizer_;
  std::unique_ptr<GeometryFilter> geometry_filter_;  // null without the geometry check
  std::unique_ptr<LoopCloser> loop_closer_;  // null without loop closing or in localization mode
  std::unique_ptr<Tracker> tracker_;
  long next_frame_id_ = 0;
  mutable std::mutex records_mutex_;
  std::vector<FrameRecord> records_;
  bool shut_down_ = false;
};

}  // namespace esdslam
