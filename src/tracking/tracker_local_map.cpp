// Tracker: local-map tracking and keyframe decision / creation.
#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_set>

#include <Eigen/Eigenvalues>

#include "map/keyframe.h"
#include "map/map_point.h"
#include "tracking/frame_matcher.h"
#include "tracking/frame_pose.h"
#include "tracking/tracker.h"

namespace esdslam {

bool Tracker::TrackLocalMap(Frame* frame) {
  UpdateLocalKeyFrames(frame);
  UpdateLocalPoints();
  SearchLocalPoints(frame);
  const bool prior_on = options_.motion_prior_below_matches > 0;
  int matches = 0;
  if (prior_on)
    for (int i = 0; i < frame->size(); ++i) matches += frame->map_points[i] != nullptr;
  std::optional<PosePrior> prior = prior_on ? MotionPrior(matches) : std::nullopt;
  if (options_.depth_prior)
    if (std::optional<PosePrior> depth = DepthPrior(*frame)) prior = depth;
  OptimizeFramePose(frame, options_.pose, prior ? &*prior : nullptr);
  inliers_ = 0;
  for (int i = 0; i < frame->size(); ++i) {
    MapPoint* point = frame->map_points[i];
    if (point == nullptr || frame->outlier[i]) continue;
    point->IncreaseFound();
    if (point->num_observations() > 0) ++inliers_;
  }
  if (prior_on && !prior && inliers_ >= options_.min_local_map_inliers) LearnPredictionError(*frame);
  if (RecentlyRelocalized(*frame, options_.max_frames_between_keyframes))
    return inliers_ >= std::max(options_.min_local_map_inliers, options_.relocalized_min_inliers);
  return inliers_ >= options_.min_local_map_inliers;
}

// The Gaussian prior at the constant-velocity prediction when the matches are few (see
// TrackerOptions::motion_prior_below_matches); none before 5 well-matched frames taught its sigmas.
std::optional<PosePrior> Tracker::MotionPrior(int matches) const {
  if (!predicted_cam_from_world_ || matches >= options_.motion_prior_below_matches || prediction_error_samples_ < 5)
    return std::nullopt;
  PosePrior prior;
  prior.cam_from_world = *predicted_cam_from_world_;
  prior.sigma_translation_m = std::max(options_.motion_prior_min_sigma_m, std::sqrt(prediction_error_t2_ / 3.0));
  prior.sigma_rotation_rad = std::max(options_.motion_prior_min_sigma_rad, std::sqrt(prediction_error_r2_ / 3.0));
  return prior;
}

// The depth alignment to the previous frame (TrackerOptions::depth_prior) as a prior with its
// information matrix (S = sqrt(Lambda) V^T of its eigen-decomposition, so S^T S = information).
std::optional<PosePrior> Tracker::DepthPrior(const Frame& frame) {
  if (!predicted_cam_from_world_ || !last_frame_.has_pose || last_frame_.depth_m().empty()) return std::nullopt;
  if (!depth_aligner_) depth_aligner_ = std::make_unique<DepthAligner>(frame.rig().camera, options_.depth_alignment);
  const std::optional<DepthAlignment> aligned =
      depth_aligner_->Align(frame.depth_m(), frame.dynamic_mask(), last_frame_.depth_m(), last_frame_.dynamic_mask(),
                            last_frame_.cam_from_world, frame.cam_from_world);
  if (!aligned) return std::nullopt;
  // The samples' errors are not independent (the sensor's depth distortion is smooth across the
  // image, the previous frame's pose error is common to all): each counts as depth_prior_weight
  // of an independent reading.
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eigen(aligned->information * options_.depth_prior_weight);
  if (eigen.info() != Eigen::Success) return std::nullopt;
  PosePrior prior;
  prior.cam_from_world = aligned->cam_from_world;
  prior.sqrt_information = eigen.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal() * eigen.eigenvectors().transpose();
  return prior;
}

// Running mean (weight 1/20) of the squared prediction errors, from frames tracked without the
// prior (so the prior never teaches itself).
void Tracker::LearnPredictionError(const Frame& frame) {
  if (!predicted_cam_from_world_) return;
  const Rigid3 error = frame.cam_from_world * predicted_cam_from_world_->inverse();
  const double t2 = error.translation().squaredNorm(), r2 = LogSO3(error.rotation_matrix()).squaredNorm();
  const double weight = prediction_error_samples_ < 20 ? 1.0 / (prediction_error_samples_ + 1) : 1.0 / 20;
  prediction_error_t2_ += weight * (t2 - prediction_error_t2_);
  prediction_error_r2_ += weight * (r2 - prediction_error_r2_);
  ++prediction_error_samples_;
}

// Local keyframes: those observing the frame's points, then up to 10 best covisible keyframes,
// a child and the parent of each. The reference keyframe is the one sharing the most points.
void Tracker::UpdateLocalKeyFrames(Frame* frame) {
  frame->DropBadAssociations();
  std::map<KeyFrame*, int, KeyFrameIdLess> counts;
  for (int i = 0; i < frame->size(); ++i) {
    MapPoint* point = frame->map_points[i];
    if (point == nullptr) continue;
    for (KeyFrame* keyframe : point->observing_keyframes()) ++counts[keyframe];
  }
  if (counts.empty()) return;
  local_keyframes_.clear();
  std::unordered_set<const KeyFrame*> chosen;
  KeyFrame* best = nullptr;
  int best_count = 0;
  for (const auto& [keyframe, count] : counts) {
    if (keyframe->is_bad()) continue;
    if (count > best_count) best_count = count, best = keyframe;
    local_keyframes_.push_back(keyframe);
    chosen.insert(keyframe);
  }
  const std::vector<KeyFrame*> first_ring = local_keyframes_;
  const auto try_add = [&](KeyFrame* keyframe) {
    if (keyframe == nullptr || keyframe->is_bad() || !chosen.insert(keyframe).second) return false;
    local_keyframes_.push_back(keyframe);
    return true;
  };
  for (KeyFrame* keyframe : first_ring) {
    if (static_cast<int>(local_keyframes_.size()) >= options_.max_local_keyframes) break;
    for (KeyFrame* neighbour : keyframe->BestCovisibleKeyframes(10))
      if (try_add(neighbour)) break;
    for (KeyFrame* child : keyframe->children())
      if (try_add(child)) break;
    try_add(keyframe->parent());
  }
  if (best != nullptr) {
    reference_keyframe_ = best;
    frame->reference_keyframe = best;
  }
}

void Tracker::UpdateLocalPoints() {
  local_points_.clear();
  std::unordered_set<const MapPoint*> added;
  for (KeyFrame* keyframe : local_keyframes_)
    for (MapPoint* point : keyframe->valid_map_points())
      if (added.insert(point).second) local_points_.push_back(point);
}

// Projects the local points not yet matched (nor dropped) in this frame and matches those in view.
void Tracker::SearchLocalPoints(Frame* frame) {
  frame->DropBadAssociations();
  for (int i = 0; i < frame->size(); ++i) {
    MapPoint* point = frame->map_points[i];
    if (point == nullptr) continue;
    point->IncreaseVisible();
    seen_this_frame_.insert(point);
  }
  std::vector<PointProjection> in_view;
  for (MapPoint* point : local_points_) {
    if (seen_this_frame_.count(point) > 0 || point->is_bad()) continue;
    if (std::optional<PointProjection> projection = frame->ProjectInFrustum(point, 0.5)) {
      point->IncreaseVisible();
      in_view.push_back(*projection);
    }
  }
  const double radius_factor = RecentlyRelocalized(*frame, 2) ? options_.relocalized_search_radius_factor
                                                             : options_.local_search_radius_factor;
  if (!in_view.empty()) ApplyMatches(esdslam::SearchLocalPoints(*frame, in_view, radius_factor), frame);
}

// ORB-SLAM2's RGB-D rule: insert when the frame tracks few close points but could add many, or
// when too many frames passed, or tracking weakened relative to the reference keyframe.
bool Tracker::NeedNewKeyFrame(const Frame& frame) const {
  if (RecentlyRelocalized(frame, options_.max_frames_between_keyframes)) return false;
  const int num_keyframes = map_->num_keyframes();
  const int min_observations = num_keyframes <= 2 ? 2 : 3;
  const int reference_matches = reference_keyframe_->TrackedMapPoints(min_observations);
  const bool mapping_idle = sink_ == nullptr || sink_->AcceptsKeyFrames();
  int tracked_close = 0, untracked_close = 0;
  for (int i = 0; i < frame.size(); ++i) {
    if (!frame.features().is_close(i) || frame.features().is_dynamic[i]) continue;
    if (frame.map_points[i] != nullptr && !frame.outlier[i]) ++tracked_close;
    else ++untracked_close;
  }
  const bool need_close = tracked_close < 100 && untracked_close > 70;
  const double ref_ratio = num_keyframes < 2 ? 0.4 : 0.75;
  const long since_last = frame.id() - last_keyframe_frame_id_;
  const bool too_long = since_last >= options_.max_frames_between_keyframes;
  const bool idle_and_due = since_last >= options_.min_frames_between_keyframes && mapping_idle;
  const bool weak = inliers_ < reference_matches * 0.25 || need_close;
  const bool enough_new = (inliers_ < reference_matches * ref_ratio || need_close) && inliers_ > 15;
  if (!((too_long || idle_and_due || weak) && enough_new)) return false;
  if (mapping_idle) return true;
  sink_->InterruptBundleAdjustment();
  return sink_->QueuedKeyFrames() < 3;
}

KeyFrame* Tracker::CreateNewKeyFrame(Frame* frame) {
  KeyFrame* keyframe = map_->CreateKeyFrame(frame->id(), frame->timestamp(), frame->shared_features(), frame->cam_from_world);
  for (int i = 0; i < frame->size(); ++i) {
    MapPoint* point = frame->map_points[i];
    if (point != nullptr && !frame->outlier[i] && !point->is_bad() && point->num_observations() > 0)
      keyframe->AddMapPoint(point, i);
  }
  const FeatureSet& features = frame->features();
  std::vector<std::pair<float, int>> by_depth;
  for (int i = 0; i < frame->size(); ++i)
    if (features.has_depth(i) && !features.is_dynamic[i]) by_depth.emplace_back(features.depth[i], i);
  std::sort(by_depth.begin(), by_depth.end());
  int count = 0;
  for (const auto& [depth, i] : by_depth) {
    if (keyframe->map_point(i) == nullptr) {
      frame->map_points[i] = CreatePointFromDepth(keyframe, *frame, i);
      frame->outlier[i] = false;
    }
    ++count;
    if (depth > features.rig->th_depth_m && count > options_.max_depth_points) break;
  }
  reference_keyframe_ = last_keyframe_ = keyframe;
  frame->reference_keyframe = keyframe;
  last_keyframe_frame_id_ = frame->id();
  return keyframe;
}

MapPoint* Tracker::CreatePointFromDepth(KeyFrame* keyframe, const Frame& frame, int index) {
  const Vec3 position_world = frame.cam_from_world.inverse() * frame.features().BackprojectCam(index);
  MapPoint* point = map_->CreateMapPoint(position_world, keyframe);
  point->AddObservation(keyframe, index, true);
  keyframe->AddMapPoint(point, index);
  point->ComputeDistinctiveDescriptor();
  point->UpdateNormalAndDepth();
  map_->AddMapPoint(point);
  return point;
}

}  // namespace esdslam
