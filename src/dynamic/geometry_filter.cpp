#include "dynamic/geometry_filter.h"

#include <algorithm>
#include <map>

#include "common/error.h"
#include "common/timer.h"
#include "dynamic/reference_keyframes.h"
#include "map/keyframe.h"
#include "map/map_point.h"
#include "tracking/frame.h"

namespace esdslam {

void GeometryFilterOptions::Check() const {
  check.Check();
  if (reference_keyframes < 1) throw Error("geometry filter: reference_keyframes must be >= 1");
  if (keyframe_depth_capacity < 0) throw Error("geometry filter: keyframe_depth_capacity must be >= 0");
  if (!(keyframe_depth_scale > 0 && keyframe_depth_scale <= 1))
    throw Error("geometry filter: keyframe_depth_scale must be in (0, 1]");
  if (cull_after_frames < 0) throw Error("geometry filter: cull_after_frames must be >= 0");
}

GeometryFilter::GeometryFilter(const GeometryFilterOptions& options)
    : options_(options),
      depths_(options.keyframe_depth_capacity, options.keyframe_depth_scale),
      votes_(std::max(1, options.cull_after_frames)) {
  options_.Check();
}

int GeometryFilter::Apply(Frame* frame) {
  Stopwatch watch;
  ThreadCpuStopwatch cpu;
  last_ = {};
  last_.image_motion_px = ImageMotionSinceLastFrame(*frame);
  last_frame_id_ = frame->id();
  last_cam_from_world_ = frame->cam_from_world;
  const std::vector<KeyFrame*> keyframes = SelectKeyFrames(*frame);
  last_.reference_keyframes = static_cast<int>(keyframes.size());
  if (keyframes.empty()) return 0;
  std::vector<std::vector<int>> keypoints;
  const std::vector<ReferenceKeyframe> references = BuildReferences(keyframes, &keypoints);
  const GeometryCheckResult result =
      CheckMultiViewGeometry(frame->rig().camera, frame->cam_from_world, frame->depth_m(), references, options_.check,
                             frame->geometry_exempt, last_.image_motion_px);
  last_.ran = true;
  last_.window_radius_px = result.window_radius_px;
  last_.skipped_fast_motion = result.skipped_fast_motion;
  last_.tested = result.num_tested;
  last_.covered = static_cast<int>(result.dynamic_points.size());
  last_.vanished = static_cast<int>(result.vanished_points.size());
  last_.mask = result.dynamic_mask;
  const int removed = FlagKeypoints(frame, result.dynamic_mask);
  VoteReferencePoints(keyframes, keypoints, result);
  CullMovedPoints(frame);
  last_.check_ms = watch.ElapsedMs();
  last_.check_cpu_ms = cpu.ElapsedMs();
  return removed;
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
    for (const auto& [keyframe, index] : point->observations()) {
      (void)index;
      ++shared[keyframe];
    }
  }
  std::vector<KeyFrame*> candidates;
  std::vector<int> counts;
  for (const auto& [keyframe, count] : shared) {
    if (keyframe->is_bad()) continue;
    candidates.push_back(keyframe);
    counts.push_back(count);
  }
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
int GeometryFilter::FlagKeypoints(Frame* frame, const cv::Mat& mask) {
  if (cv::countNonZero(mask) == 0) return 0;
  const FeatureSet& features = frame->features();
  int removed = 0;
  for (int i = 0; i < frame->size(); ++i) {
    if (features.is_dynamic[i]) continue;
    const cv::Point2f& pt = features.keypoints[i].pt;
    const int u = std::clamp(cvRound(pt.x), 0, mask.cols - 1), v = std::clamp(cvRound(pt.y), 0, mask.rows - 1);
    if (!mask.at<std::uint8_t>(v, u)) continue;
    MapPoint* point = frame->map_points[i];
    if (point != nullptr) {
      ++removed;
      if (point->num_observations() > 0 && !point->is_bad()) Evidence(point);
    }
    frame->MarkDynamic(i, kDynamicByGeometry);
    ++last_.flagged_keypoints;
  }
  last_.associations_removed = removed;
  return removed;
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

void GeometryFilter::CullMovedPoints(Frame* frame) {
  const std::vector<long> moved = votes_.EndFrame();
  if (options_.cull_after_frames > 0) {
    for (const long id : moved) {
      MapPoint* point = evidence_points_.at(id);
      if (point->is_bad()) continue;
      point->SetBad();
      ++last_.points_culled;
    }
  }
  evidence_points_.clear();
  total_culled_ += last_.points_culled;
  if (last_.points_culled == 0) return;
  for (int i = 0; i < frame->size(); ++i) {
    MapPoint* point = frame->map_points[i];
    if (point != nullptr && point->is_bad()) frame->map_points[i] = nullptr;
  }
}

}  // namespace esdslam
