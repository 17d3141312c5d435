#include "tracking/tracker.h"

#include <algorithm>

#include <spdlog/spdlog.h>

#include "common/error.h"
#include "map/keyframe.h"
#include "map/map_point.h"
#include "tracking/frame_matcher.h"
#include "tracking/frame_pose.h"
#include "tracking/moving_keypoint_filter.h"
#include "tracking/relocalizer.h"

namespace esdslam {
namespace {

// Rolling shutter: the keypoints moved to the middle row's time, for the rotation rate of the
// camera motion cam_from_last over interval_s (nothing for a global-shutter rig or a bad interval).
void CompensateRollingShutter(const Rigid3& cam_from_last, double interval_s, Frame* frame) {
  if (frame->rig().readout_time_s <= 0.0 || !(interval_s > 0.0)) return;
  frame->CompensateRollingShutter(LogSO3(cam_from_last.rotation().toRotationMatrix()) / interval_s);
}

}  // namespace

const char* ToString(TrackingState state) {
  switch (state) {
    case TrackingState::kNotInitialized: return "NOT_INITIALIZED";
    case TrackingState::kOk: return "OK";
    case TrackingState::kLost: return "LOST";
  }
  return "?";
}

void TrackerOptions::Check() const {
  if (min_initial_depth_keypoints < 1) throw Error("tracker: min_initial_depth_keypoints must be >= 1");
  if (max_frames_between_keyframes < 1 || min_frames_between_keyframes < 0)
    throw Error("tracker: keyframe frame limits must be positive");
  if (!(motion_search_radius_px > 0) || !(local_search_radius_factor > 0))
    throw Error("tracker: search radii must be positive");
  if (min_local_map_inliers < 3 || min_pose_matches < 3 || relocalized_min_inliers < 3)
    throw Error("tracker: inlier thresholds must be >= 3");
  if (!(relocalized_search_radius_factor > 0)) throw Error("tracker: relocalized_search_radius_factor must be positive");
  if (min_motion_matches < 3) throw Error("tracker: min_motion_matches must be >= 3");
  if (max_local_keyframes < 1) throw Error("tracker: max_local_keyframes must be >= 1");
  if (max_depth_points < 0) throw Error("tracker: max_depth_points must be >= 0");
  if (max_coasted_frames < 0) throw Error("tracker: max_coasted_frames must be >= 0");
  if (motion_prior_below_matches < 0) throw Error("tracker: motion_prior_below_matches must be >= 0");
  depth_alignment.Check();
  if (!(depth_prior_weight > 0 && depth_prior_weight <= 1)) throw Error("tracker: depth_prior_weight must be in (0, 1]");
  if (!(motion_prior_min_sigma_m > 0 && motion_prior_min_sigma_m < 1) ||
      !(motion_prior_min_sigma_rad > 0 && motion_prior_min_sigma_rad < 1))
    throw Error("tracker: motion_prior_min_sigma_m / _rad must be in (0, 1)");
  pose.Check();
}

Tracker::Tracker(Map* map, KeyFrameSink* sink, const TrackerOptions& options)
    : map_(map), sink_(sink), options_(options) {
  options_.Check();
}

TrackingResult Tracker::Track(Frame* frame, MovingKeypointFilter* moving_filter) {
  TrackingResult result;
  {
    std::lock_guard<std::mutex> lock(map_->update_mutex());
    seen_this_frame_.clear();
    bool tracked = false;
    if (state_ == TrackingState::kNotInitialized) {
      tracked = Initialize(frame);
      if (tracked) result.new_keyframe = last_keyframe_;
    } else {
      predicted_cam_from_world_.reset();
      if (state_ == TrackingState::kOk && velocity_valid_) predicted_cam_from_world_ = velocity_ * last_frame_.cam_from_world;
      if (state_ == TrackingState::kOk) {
        ReplaceMovedPointsInLastFrame();
        if (velocity_valid_) CompensateRollingShutter(velocity_, velocity_interval_s_, frame);
        if (velocity_valid_) tracked = TrackWithMotionModel(frame);
        if (!tracked) tracked = TrackReferenceKeyFrame(frame);
        // Again with this frame's own rotation rate, now that it has a pose.
        if (tracked && last_frame_.has_pose)
          CompensateRollingShutter(frame->cam_from_world * last_frame_.cam_from_world.inverse(),
                                   frame->timestamp() - last_frame_.timestamp(), frame);
      } else {
        // LOST: global BoW relocalization, else retry against the last local map.
        if (relocalizer_ != nullptr) tracked = Relocalize(frame);
        if (!tracked) tracked = TrackReferenceKeyFrame(frame);
      }
      frame->reference_keyframe = reference_keyframe_;
      if (tracked && moving_filter != nullptr) FilterMovingKeypoints(frame, moving_filter);
      if (tracked) tracked = TrackLocalMap(frame);
      // No keyframe while local mapping is paused for a loop correction (reservation refused).
      if (tracked && !options_.localization_only && NeedNewKeyFrame(*frame) &&
          (sink_ == nullptr || sink_->ReserveKeyFrame()))
        result.new_keyframe = CreateNewKeyFrame(frame);
      result.coasted = !tracked && Coast(frame);
      if (!result.coasted) coasted_frames_ = 0;
      tracked = tracked || result.coasted;
      state_ = tracked ? TrackingState::kOk : TrackingState::kLost;
    }
    if (result.new_keyframe != nullptr && moving_filter != nullptr) moving_filter->AddKeyFrame(*result.new_keyframe, *frame);
    Finish(frame, tracked);
    seen_this_frame_.clear();
    result.state = state_;
    result.has_pose = frame->has_pose;
    result.cam_from_world = frame->cam_from_world;
    result.reference_keyframe = frame->reference_keyframe;
    result.inliers = inliers_;  // 0 for a coasted frame (Coast)
  }
  if (result.new_keyframe != nullptr) {
    if (sink_ != nullptr) sink_->InsertKeyFrame(result.new_keyframe);
    else map_->AddKeyFrame(result.new_keyframe);
  }
  return result;
}

bool Tracker::Initialize(Frame* frame) {
  int usable = 0;
  for (int i = 0; i < frame->size(); ++i) usable += frame->features().has_depth(i) && !frame->features().is_dynamic[i];
  if (usable <= options_.min_initial_depth_keypoints) return false;
  frame->cam_from_world = Rigid3::Identity();
  frame->has_pose = true;
  KeyFrame* keyframe = map_->CreateKeyFrame(frame->id(), frame->timestamp(), frame->shared_features(), frame->cam_from_world);
  map_->AddKeyFrame(keyframe);
  for (int i = 0; i < frame->size(); ++i) {
    if (!frame->features().has_depth(i) || frame->features().is_dynamic[i]) continue;
    frame->map_points[i] = CreatePointFromDepth(keyframe, *frame, i);
  }
  spdlog::info("tracking: map initialised with {} points from frame {}", map_->num_map_points(), frame->id());
  frame->reference_keyframe = keyframe;
  reference_keyframe_ = last_keyframe_ = keyframe;
  last_keyframe_frame_id_ = frame->id();
  local_keyframes_ = {keyframe};
  local_points_ = keyframe->valid_map_points();
  state_ = TrackingState::kOk;
  velocity_valid_ = false;
  inliers_ = static_cast<int>(local_points_.size());
  return true;
}

// The last frame may hold points that local mapping has since fused into others.
void Tracker::ReplaceMovedPointsInLastFrame() {
  for (MapPoint*& point : last_frame_.map_points) {
    if (point == nullptr) continue;
    MapPoint* replacement = point->replaced_by();
    if (replacement != point) point = replacement->is_bad() ? nullptr : replacement;
  }
}

// Re-derives the last frame's pose from its reference keyframe (which local BA may have moved)
// and adds temporary points from its close depth measurements so the motion model has matches
// even where the map is thin.
void Tracker::UpdateLastFrame() {
  temporary_points_.clear();
  KeyFrame* reference = LiveAncestor(last_frame_.reference_keyframe, &last_cam_from_reference_);
  last_frame_.reference_keyframe = reference;
  if (reference != nullptr && last_frame_.has_pose) last_frame_.cam_from_world = last_cam_from_reference_ * reference->cam_from_world();
  if (!options_.last_frame_depth_points || last_keyframe_frame_id_ == last_frame_.id()) return;
  const FeatureSet& features = last_frame_.features();
  std::vector<std::pair<float, int>> by_depth;
  for (int i = 0; i < last_frame_.size(); ++i)
    if (features.has_depth(i) && !features.is_dynamic[i]) by_depth.emplace_back(features.depth[i], i);
  std::sort(by_depth.begin(), by_depth.end());
  const Rigid3 world_from_cam = last_frame_.cam_from_world.inverse();
  int count = 0;
  for (const auto& [depth, i] : by_depth) {
    MapPoint* existing = last_frame_.map_points[i];
    if (existing == nullptr || existing->num_observations() < 1) {
      auto point = std::make_unique<MapPoint>(-1 - static_cast<long>(temporary_points_.size()),
                                              world_from_cam * features.BackprojectCam(i), nullptr, map_);
      point->set_descriptor(features.descriptors.row(i));
      last_frame_.map_points[i] = point.get();
      last_frame_.outlier[i] = false;
      temporary_points_.push_back(std::move(point));
    }
    ++count;
    if (depth > features.rig->th_depth_m && count > options_.max_depth_points) break;
  }
}

bool Tracker::TrackWithMotionModel(Frame* frame) {
  UpdateLastFrame();
  frame->cam_from_world = velocity_ * last_frame_.cam_from_world;
  FrameMatches matches = SearchByProjection(*frame, last_frame_, options_.motion_search_radius_px);
  if (matches.count < options_.min_motion_matches)
    matches = SearchByProjection(*frame, last_frame_, 2 * options_.motion_search_radius_px);
  ApplyMatches(matches, frame);
  if (matches.count < options_.min_motion_matches) return false;
  OptimizeFramePose(frame, options_.pose);
  return DiscardOutliers(frame) >= options_.min_pose_matches;
}

// Matches the frame against the reference keyframe (when LOST: the best of the reference, its
// best covisible keyframes and the last keyframe), starting from the last known pose.
bool Tracker::TrackReferenceKeyFrame(Frame* frame) {
  if (reference_keyframe_ == nullptr) return false;
  Rigid3 unused;
  if (reference_keyframe_->is_bad()) reference_keyframe_ = LiveAncestor(reference_keyframe_, &unused);
  std::vector<KeyFrame*> candidates{reference_keyframe_};
  if (state_ == TrackingState::kLost) {
    for (KeyFrame* covisible : reference_keyframe_->BestCovisibleKeyframes(4)) candidates.push_back(covisible);
    KeyFrame* last = LiveAncestor(last_keyframe_, &unused);
    if (std::find(candidates.begin(), candidates.end(), last) == candidates.end()) candidates.push_back(last);
  }
  FrameMatches best;
  best.count = -1;
  for (KeyFrame* candidate : candidates) {
    FrameMatches matches = SearchKeyFrameBruteForce(*candidate, *frame);
    if (matches.count > best.count) best = std::move(matches);
  }
  frame->map_points = std::move(best.map_points);
  std::fill(frame->outlier.begin(), frame->outlier.end(), false);
  if (best.count < 15) return false;
  // Start from the last tracked pose, re-derived from its reference keyframe (which local BA or a
  // loop correction may have moved since).
  Rigid3 cam_from_good_reference = last_good_cam_from_reference_;
  KeyFrame* good_reference = LiveAncestor(last_good_reference_, &cam_from_good_reference);
  frame->cam_from_world = good_reference != nullptr ? cam_from_good_reference * good_reference->cam_from_world()
                                                    : reference_keyframe_->cam_from_world();
  OptimizeFramePose(frame, options_.pose);
  return DiscardOutliers(frame) >= options_.min_pose_matches;
}

// Geometry check on the first pose: the keypoints it finds moving become dynamic; without their
// matches the pose is estimated again (when enough are left), so that local-map tracking starts
// from an unbiased pose.
void Tracker::FilterMovingKeypoints(Frame* frame, MovingKeypointFilter* filter) {
  const MovingKeypoints moving = filter->FindMoving(*frame);
  for (int i : moving.keypoints) frame->MarkDynamic(i, kDynamicByGeometry);
  if (moving.points_culled > 0) frame->DropBadAssociations();
  if (moving.associations_removed == 0) return;
  int kept = 0;
  for (int i = 0; i < frame->size(); ++i)
    kept += frame->map_points[i] != nullptr && !frame->outlier[i] && frame->map_points[i]->num_observations() > 0;
  if (kept < options_.min_pose_matches) return;
  OptimizeFramePose(frame, options_.pose);
  DiscardOutliers(frame);
}

// A blind frame (too few static keypoints to reach min_local_map_inliers) after OK tracking:
// the motion model's pose, without map associations, for up to max_coasted_frames in a row.
bool Tracker::Coast(Frame* frame) {
  if (state_ != TrackingState::kOk || !velocity_valid_ || coasted_frames_ >= options_.max_coasted_frames) return false;
  int static_keypoints = 0;
  for (int i = 0; i < frame->size(); ++i) static_keypoints += !frame->features().is_dynamic[i];
  if (static_keypoints >= options_.min_local_map_inliers) return false;
  ++coasted_frames_;
  frame->cam_from_world = velocity_ * last_frame_.cam_from_world;
  std::fill(frame->map_points.begin(), frame->map_points.end(), nullptr);
  std::fill(frame->outlier.begin(), frame->outlier.end(), false);
  frame->reference_keyframe = reference_keyframe_;
  inliers_ = 0;
  return true;
}

// Drops outlier matches; returns the matches left with real (non-temporary) map points.
int Tracker::DiscardOutliers(Frame* frame) {
  int map_matches = 0;
  for (int i = 0; i < frame->size(); ++i) {
    MapPoint* point = frame->map_points[i];
    if (point == nullptr) continue;
    if (frame->outlier[i]) {
      frame->map_points[i] = nullptr;
      frame->outlier[i] = false;
      seen_this_frame_.insert(point);
    } else if (point->num_observations() > 0) {
      ++map_matches;
    }
  }
  return map_matches;
}

void Tracker::Finish(Frame* frame, bool tracked) {
  frame->has_pose = tracked;
  if (tracked) {
    velocity_valid_ = last_frame_.valid() && last_frame_.has_pose;
    if (velocity_valid_) velocity_ = frame->cam_from_world * last_frame_.cam_from_world.inverse();
    if (velocity_valid_) velocity_interval_s_ = frame->timestamp() - last_frame_.timestamp();
    for (int i = 0; i < frame->size(); ++i) {
      MapPoint* point = frame->map_points[i];
      if (point == nullptr) continue;
      if (frame->outlier[i] || point->num_observations() < 1) frame->map_points[i] = nullptr;
      frame->outlier[i] = false;
    }
    if (frame->reference_keyframe == nullptr) frame->reference_keyframe = reference_keyframe_;
    last_cam_from_reference_ = frame->cam_from_world * frame->reference_keyframe->world_from_cam();
    last_good_reference_ = frame->reference_keyframe;
    last_good_cam_from_reference_ = last_cam_from_reference_;
  } else {
    velocity_valid_ = false;
    std::fill(frame->map_points.begin(), frame->map_points.end(), nullptr);
  }
  temporary_points_.clear();
  last_frame_ = *frame;
}

}  // namespace esdslam
