#include "dynamic/geometry_filter.h"

#include <algorithm>
#include <map>

#include "common/error.h"
#include "common/timer.h"
#include "dynamic/reference_keyframes.h"
#include "map/keyframe.h"
#include "common/setting_error.h"
#include "map/map_point.h"
#include "tracking/frame.h"

namespace esdslam {

void GeometryFilterOptions::Check() const {
  check.Check();
  CheckRange("Dynamic.check.referenceKeyframes", reference_keyframes, 1, 100);
  CheckRange("Dynamic.check.minReferenceAge", min_reference_age_s, 0.0, 10.0);
  CheckRange("Dynamic.check.keyframeDepthCapacity", keyframe_depth_capacity, 0, 100000);
  CheckRange("Dynamic.check.keyframeDepthScale", keyframe_depth_scale, 0.05, 1.0);
  CheckRange("Dynamic.check.cullAfterFrames", cull_after_frames, 0, 1000);
}

GeometryFilter::GeometryFilter(const GeometryFilterOptions& options)
    : options_(options),
      depths_(options.keyframe_depth_capacity, options.keyframe_depth_scale),
      votes_(std::max(1, options.cull_after_frames)) {
  options_.Check();
}

GeometryFilterStats GeometryFilter::Apply(const Frame& frame) {
  Stopwatch watch;
  ThreadCpuStopwatch cpu;
  GeometryFilterStats stats;
  stats.image_motion_px = ImageMotionSinceLastFrame(frame);
  last_frame_id_ = frame.id();
  last_cam_from_world_ = frame.cam_from_world;
  const std::vector<KeyFrame*> keyframes = SelectKeyFrames(frame);
  stats.reference_keyframes = static_cast<int>(keyframes.size());
  if (keyframes.empty()) return stats;
  std::vector<std::vector<int>> keypoints;
  const std::vector<ReferenceKeyframe> references = BuildReferences(keyframes, &keypoints);
  const GeometryCheckResult result =
      CheckMultiViewGeometry(frame.rig().camera, frame.cam_from_world, frame.depth_m(), references, options_.check,
                             frame.geometry_exempt, stats.image_motion_px);
  stats.ran = true;
  stats.window_radius_px = result.window_radius_px;
  stats.skipped_fast_motion = result.skipped_fast_motion;
  stats.tested = result.num_tested;
  stats.covered = static_cast<int>(result.dynamic_points.size());
  stats.vanished = static_cast<int>(result.vanished_points.size());
  stats.mask = result.dynamic_mask;
  Flagged flagged = FlagKeypoints(frame, result.dynamic_mask);
  stats.flagged_keypoints = std::move(flagged.keypoints);
  stats.associations_removed = flagged.associations_removed;
  VoteReferencePoints(keyframes, keypoints, result);
  stats.points_culled = CullMovedPoints(&stats.culled_positions);
  stats.check_ms = watch.ElapsedMs();
  stats.check_cpu_ms = cpu.ElapsedMs();
  return stats;
}

MovingKeypoints GeometryFilterHook::FindMoving(const Frame& frame) {
  stats_ = filter_->Apply(frame);
  MovingKeypoints moving;
  moving.keypoints = stats_.flagged_keypoints;
  moving.associations_removed = stats_.associations_removed;
  moving.points_culled = stats_.points_culled;
  return moving;
}

void GeometryFilter::AddKeyFrame(const KeyFrame& keyframe, const Frame& frame) {
  if (frame.id() > last_frame_id_) {  // e.g. the first keyframe: the next frame's motion is measured from it
    last_frame_id_ = frame.id();
    last_cam_from_world_ = frame.cam_from_world;
  }
  if (options_.keyframe_depth_capacity == 0 || frame.depth_m().empty()) return;
  for (auto it = depth_owners_.begin(); it != depth_owners_.end();) {  // culled keyframes: drop their depth
    if (it->second->is_bad()) {
      depths_.Erase(it->first);
      it = depth_owners_.erase(it);
    } else {
      ++it;
    }
  }
  depths_.Add(keyframe.id(), frame.depth_m());
  depth_owners_[keyframe.id()] = &keyframe;
  for (auto it = depth_owners_.begin(); it != depth_owners_.end();)  // dropped by capacity
    it = depths_.Contains(it->first) ? std::next(it) : depth_owners_.erase(it);
}

// Per frame, at the median depth of the frame's keypoints; 0 without a previous checked frame.
double GeometryFilter::ImageMotionSinceLastFrame(const Frame& frame) const {
  if (last_frame_id_ < 0 || frame.id() <= last_frame_id_) return 0;
  std::vector<float> depths;
  for (const float depth : frame.features().depth)
    if (depth > 0) depths.push_back(depth);
  if (depths.empty()) return 0;
  std::nth_element(depths.begin(), depths.begin() + depths.size() / 2, depths.end());
  const Rigid3 current_from_last = frame.cam_from_world * last_cam_from_world_.inverse();
  return ImageMotionPx(frame.rig().camera, current_from_last, depths[depths.size() / 2]) /
         static_cast<double>(frame.id() - last_frame_id_);
}

std::vector<KeyFrame*> GeometryFilter::SelectKeyFrames(const Frame& frame) const {
  std::map<KeyFrame*, int, KeyFrameIdLess> shared;
  for (int i = 0; i < frame.size(); ++i) {
    MapPoint* point = frame.map_points[i];
    if (point == nullptr || frame.outlier[i] || point->is_bad()) continue;
    for (KeyFrame* keyframe : point->observing_keyframes()) ++shared[keyframe];
  }
  std::vector<KeyFrame*> candidates;
  std::vector<int> counts;
  std::vector<double> times_s;
  for (const auto& [keyframe, count] : shared) {
    if (keyframe->is_bad()) continue;
    candidates.push_back(keyframe);
    counts.push_back(count);
    times_s.push_back(keyframe->timestamp());
  }
  counts = WithoutYoungKeyframes(counts, times_s, frame.timestamp(), options_.min_reference_age_s);
  std::vector<KeyFrame*> chosen;
  for (const int k : SelectReferenceKeyframes(counts, options_.reference_keyframes)) chosen.push_back(candidates[k]);
  return chosen;
}

std::vector<ReferenceKeyframe> GeometryFilter::BuildReferences(const std::vector<KeyFrame*>& keyframes,
                                                               std::vector<std::vector<int>>* keypoints) {
  std::vector<ReferenceKeyframe> references(keyframes.size());
  keypoints->assign(keyframes.size(), {});
  for (std::size_t k = 0; k < keyframes.size(); ++k) {
    const FeatureSet& features = keyframes[k]->features();
    ReferenceKeyframe& reference = references[k];
    reference.world_from_cam = keyframes[k]->world_from_cam();
    for (int i = 0; i < features.size(); ++i) {
      if (!features.has_depth(i) || features.is_dynamic[i] || features.depth[i] > options_.check.max_depth_m) continue;
      reference.points_world.push_back(reference.world_from_cam * features.BackprojectCam(i));
      (*keypoints)[k].push_back(i);
    }
    reference.depth_m = depths_.Find(keyframes[k]->id());
    reference.depth_scale = depths_.scale();
  }
  return references;
}

// Keypoints on the grown mask become dynamic; a map point matched to one of them moved with it.
GeometryFilter::Flagged GeometryFilter::FlagKeypoints(const Frame& frame, const cv::Mat& mask) {
  Flagged flagged;
  if (cv::countNonZero(mask) == 0) return flagged;
  const FeatureSet& features = frame.features();
  for (int i = 0; i < frame.size(); ++i) {
    if (features.is_dynamic[i]) continue;
    if (!KeypointOnMask(features.keypoints[i], mask)) continue;
    MapPoint* point = frame.map_points[i];
    if (point != nullptr) {
      ++flagged.associations_removed;
      if (point->num_observations() > 0 && !point->is_bad()) Evidence(point);
    }
    flagged.keypoints.push_back(i);
  }
  return flagged;
}

void GeometryFilter::VoteReferencePoints(const std::vector<KeyFrame*>& keyframes,
                                         const std::vector<std::vector<int>>& keypoints,
                                         const GeometryCheckResult& result) {
  for (std::size_t k = 0; k < keyframes.size(); ++k) {
    const std::vector<MapPoint*> points = keyframes[k]->map_points();
    for (std::size_t p = 0; p < keypoints[k].size(); ++p) {
      const PointOutcome outcome = result.outcomes[k][p];
      if (outcome != PointOutcome::kVanished && outcome != PointOutcome::kConsistent) continue;
      MapPoint* point = points[keypoints[k][p]];
      if (point == nullptr) continue;
      if (outcome == PointOutcome::kConsistent) votes_.Consistent(point->id());  // harmless for a bad point
      else if (!point->is_bad()) Evidence(point);
    }
  }
}

void GeometryFilter::Evidence(MapPoint* point) {
  votes_.Evidence(point->id());
  evidence_points_[point->id()] = point;
}

int GeometryFilter::CullMovedPoints(std::vector<Vec3>* positions) {
  const std::vector<long> moved = votes_.EndFrame();
  int culled = 0;
  if (options_.cull_after_frames > 0) {
    for (const long id : moved) {
      MapPoint* point = evidence_points_.at(id);
      if (point->is_bad()) continue;
      positions->push_back(point->position());
      point->SetBad();
      ++culled;
    }
  }
  evidence_points_.clear();
  total_culled_ += culled;
  return culled;
}

}  // namespace esdslam
