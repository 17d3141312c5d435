#include "tracking/relocalizer.h"

#include <algorithm>

#include <spdlog/spdlog.h>

#include "common/error.h"
#include "map/keyframe.h"
#include "map/map_point.h"
#include "tracking/frame_matcher.h"
#include "tracking/frame_pose.h"

namespace esdslam {

void RelocalizerOptions::Check() const {
  bow.Check();
  pnp.Check();
  if (min_bow_matches < 4) throw Error("RelocalizerOptions: min_bow_matches must be >= 4");
  if (max_candidates < 1) throw Error("RelocalizerOptions: max_candidates must be >= 1");
  if (min_final_inliers < min_optimized_inliers) throw Error("RelocalizerOptions: min_final_inliers < min_optimized_inliers");
  if (!(coarse_radius_factor > 0 && fine_radius_factor > 0)) throw Error("RelocalizerOptions: radius factors must be > 0");
}

Relocalizer::Relocalizer(PlaceRecognition* places, const RelocalizerOptions& options)
    : places_(places), options_(options) {
  if (places_ == nullptr) throw Error("Relocalizer: null place recognition");
  options_.Check();
}

namespace {

void ClearAssociations(Frame* frame) {
  std::fill(frame->map_points.begin(), frame->map_points.end(), nullptr);
  std::fill(frame->outlier.begin(), frame->outlier.end(), false);
}

// Removes outlier associations; returns the associations left.
int DropOutliers(Frame* frame) {
  int kept = 0;
  for (int i = 0; i < frame->size(); ++i) {
    if (frame->map_points[i] == nullptr) continue;
    if (frame->outlier[i]) frame->map_points[i] = nullptr, frame->outlier[i] = false;
    else ++kept;
  }
  return kept;
}

// Projects the candidate's points not yet associated and matches them in a window of
// `radius_factor`; returns the new matches.
int SearchCandidateByProjection(Frame* frame, KeyFrame* candidate, double radius_factor) {
  std::vector<PointProjection> in_view;
  std::vector<MapPoint*> already(frame->map_points);
  std::sort(already.begin(), already.end());
  for (MapPoint* point : candidate->valid_map_points()) {
    if (std::binary_search(already.begin(), already.end(), point)) continue;
    if (std::optional<PointProjection> projection = frame->ProjectInFrustum(point, 0.5)) in_view.push_back(*projection);
  }
  const FrameMatches matches = SearchLocalPoints(*frame, in_view, radius_factor);
  ApplyMatches(matches, frame);
  return matches.count;
}

}  // namespace

KeyFrame* Relocalizer::Relocalize(Frame* frame, const PoseOptimizerOptions& pose_options,
                                  const std::vector<KeyFrame*>& map_keyframes, RelocalizationStats* stats) {
  RelocalizationStats local_stats;
  places_->AddMissing(map_keyframes);
  const ImageBow frame_bow = places_->Compute(frame->features());
  std::vector<KeyFrame*> candidates = places_->RelocalizationCandidates(frame_bow);
  local_stats.candidates = static_cast<int>(candidates.size());
  if (static_cast<int>(candidates.size()) > options_.max_candidates) candidates.resize(options_.max_candidates);
  KeyFrame* found = nullptr;
  for (KeyFrame* candidate : candidates) {
    if (MatchCandidate(frame, frame_bow, candidate) < options_.min_bow_matches) continue;
    ++local_stats.tried;
    int inliers = 0;
    if (SolveCandidate(frame, candidate, pose_options, &inliers)) {
      found = candidate;
      local_stats.inliers = inliers;
      break;
    }
  }
  if (found == nullptr) ClearAssociations(frame);
  if (stats != nullptr) *stats = local_stats;
  spdlog::debug("relocalization: frame {} {} ({} candidates, {} tried, {} inliers)", frame->id(),
                found ? "found" : "failed", local_stats.candidates, local_stats.tried, local_stats.inliers);
  return found;
}

int Relocalizer::MatchCandidate(Frame* frame, const ImageBow& frame_bow, KeyFrame* candidate) const {
  ClearAssociations(frame);
  const std::shared_ptr<const ImageBow> candidate_bow = places_->KeyFrameBow(candidate);
  if (candidate_bow == nullptr) return 0;
  const std::vector<MapPoint*> candidate_points = candidate->map_points();
  std::vector<bool> train_usable(candidate_points.size());
  for (std::size_t i = 0; i < candidate_points.size(); ++i)
    train_usable[i] = candidate_points[i] != nullptr && !candidate_points[i]->is_bad();
  const FeatureSet& features = frame->features();
  std::vector<bool> query_usable(features.size());
  for (int j = 0; j < features.size(); ++j) query_usable[j] = !features.is_dynamic[j];
  const std::vector<int> query_to_train =
      MatchByDirectIndex(candidate->features(), candidate_bow->direct_index, train_usable, features,
                         frame_bow.direct_index, query_usable, options_.bow);
  int matches = 0;
  for (int j = 0; j < features.size(); ++j) {
    if (query_to_train[j] < 0) continue;
    frame->map_points[j] = candidate_points[query_to_train[j]];
    ++matches;
  }
  return matches;
}

bool Relocalizer::SolveCandidate(Frame* frame, KeyFrame* candidate, const PoseOptimizerOptions& pose_options,
                                 int* inliers) const {
  const FeatureSet& features = frame->features();
  std::vector<Vec3> points;
  std::vector<Vec2> pixels;
  std::vector<double> scales;
  std::vector<int> indices;
  for (int i = 0; i < frame->size(); ++i) {
    if (frame->map_points[i] == nullptr) continue;
    points.push_back(frame->map_points[i]->position());
    pixels.push_back(features.pixel(i));
    scales.push_back(features.rig->pyramid.scale_factors[features.level(i)]);
    indices.push_back(i);
  }
  PnpRansacOptions pnp = options_.pnp;
  pnp.seed = options_.pnp.seed + static_cast<std::uint32_t>(frame->id());
  const PnpRansacResult ransac = EstimatePnpRansac(points, pixels, features.rig->camera, pnp, scales);
  if (!ransac.success) return false;
  for (std::size_t k = 0; k < indices.size(); ++k)
    if (!ransac.inliers[k]) frame->map_points[indices[k]] = nullptr;
  frame->cam_from_world = ransac.cam_from_world;
  *inliers = OptimizeFramePose(frame, pose_options);
  if (*inliers < options_.min_optimized_inliers) return false;
  DropOutliers(frame);
  if (*inliers < options_.min_final_inliers) {
    SearchCandidateByProjection(frame, candidate, options_.coarse_radius_factor);
    *inliers = OptimizeFramePose(frame, pose_options);
    DropOutliers(frame);
    if (*inliers < options_.min_final_inliers) {
      SearchCandidateByProjection(frame, candidate, options_.fine_radius_factor);
      *inliers = OptimizeFramePose(frame, pose_options);
      DropOutliers(frame);
    }
  }
  return *inliers >= options_.min_final_inliers;
}

}  // namespace esdslam
