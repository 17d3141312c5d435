#include "loop/loop_verification.h"

#include <set>

#include "common/error.h"
#include "feature/descriptor.h"
#include "loop/loop_projection.h"
#include "map/keyframe.h"
#include "map/map_point.h"

namespace esdslam {

void LoopVerificationOptions::Check() const {
  bow.Check();
  ransac.Check();
  refinement.Check();
  if (min_bow_matches < 3 || min_refined_inliers < 3 || min_total_matches < 3)
    throw Error("loop verification: match thresholds must be >= 3");
  if (!(guided_radius_px > 0) || !(projection_radius_factor > 0))
    throw Error("loop verification: search radii must be positive");
}

namespace {

bool Live(const MapPoint* point) { return point != nullptr && !point->is_bad(); }

// Per current keypoint: the candidate's point matched to it through the direct index (both
// keypoints hold live map points), or null.
std::vector<MapPoint*> MatchByBow(KeyFrame* current, KeyFrame* candidate, const PlaceRecognition& places,
                                  const BowMatchOptions& options) {
  const auto current_bow = places.KeyFrameBow(current);
  const auto candidate_bow = places.KeyFrameBow(candidate);
  const std::vector<MapPoint*> current_points = current->map_points();
  std::vector<MapPoint*> matched(current_points.size(), nullptr);
  if (current_bow == nullptr || candidate_bow == nullptr) return matched;
  const std::vector<MapPoint*> candidate_points = candidate->map_points();
  std::vector<bool> train_usable(candidate_points.size()), query_usable(current_points.size());
  for (std::size_t i = 0; i < candidate_points.size(); ++i) train_usable[i] = Live(candidate_points[i]);
  for (std::size_t j = 0; j < current_points.size(); ++j) query_usable[j] = Live(current_points[j]);
  const std::vector<int> query_to_train =
      MatchByDirectIndex(candidate->features(), candidate_bow->direct_index, train_usable, current->features(),
                         current_bow->direct_index, query_usable, options);
  for (std::size_t j = 0; j < matched.size(); ++j)
    if (query_to_train[j] >= 0) matched[j] = candidate_points[query_to_train[j]];
  return matched;
}

struct MatchPairs {
  std::vector<PointMatch3D> pairs;
  std::vector<int> current_index;  // keypoint of the current keyframe per pair
};

// 3-D/3-D pairs (each point in its keyframe's camera frame) of the matched keypoints.
MatchPairs BuildPairs(const KeyFrame& current, const KeyFrame& candidate, const std::vector<MapPoint*>& matched) {
  MatchPairs out;
  const Rigid3 current_pose = current.cam_from_world(), candidate_pose = candidate.cam_from_world();
  const std::vector<MapPoint*> current_points = current.map_points();
  const auto& scales = current.rig().pyramid.scale_factors;
  for (std::size_t j = 0; j < matched.size(); ++j) {
    MapPoint* loop_point = matched[j];
    if (!Live(loop_point) || !Live(current_points[j])) continue;
    const int k = loop_point->KeypointIndexIn(&candidate);
    if (k < 0) continue;
    PointMatch3D pair;
    pair.point_a = current_pose * current_points[j]->position();
    pair.point_b = candidate_pose * loop_point->position();
    pair.pixel_a = current.features().pixel(static_cast<int>(j));
    pair.pixel_b = candidate.features().pixel(k);
    pair.pixel_scale_a = scales[current.features().level(static_cast<int>(j))];
    pair.pixel_scale_b = scales[candidate.features().level(k)];
    out.pairs.push_back(pair);
    out.current_index.push_back(static_cast<int>(j));
  }
  return out;
}

// Adds mutual projection matches under the estimate: an unmatched candidate point projected into
// the current keyframe and the current keyframe's point there projected back must pick each
// other (ORB-SLAM2's SearchBySim3, TH_HIGH). Returns the matches added.
int GuidedMutualMatches(KeyFrame* current, KeyFrame* candidate, const Rigid3& current_from_loop, double radius,
                        std::vector<MapPoint*>* matched) {
  const Rigid3 current_in_loop_world = current_from_loop * candidate->cam_from_world();
  const Rigid3 candidate_in_current_world = current_from_loop.inverse() * current->cam_from_world();
  const std::vector<MapPoint*> current_points = current->map_points();
  const std::vector<MapPoint*> candidate_points = candidate->map_points();
  std::vector<bool> blocked_current(current_points.size()), blocked_candidate(candidate_points.size());
  std::set<MapPoint*> used(matched->begin(), matched->end());
  for (std::size_t j = 0; j < current_points.size(); ++j)
    blocked_current[j] = !Live(current_points[j]) || (*matched)[j] != nullptr;
  for (std::size_t k = 0; k < candidate_points.size(); ++k)
    blocked_candidate[k] = !Live(candidate_points[k]) || used.count(candidate_points[k]) > 0;
  int added = 0;
  for (std::size_t k = 0; k < candidate_points.size(); ++k) {
    if (blocked_candidate[k]) continue;
    const int j = ProjectionMatch(*current, current_in_loop_world, *candidate_points[k], radius, &blocked_current,
                                  kDescriptorDistanceHigh);
    if (j < 0) continue;
    const int back = ProjectionMatch(*candidate, candidate_in_current_world, *current_points[j], radius,
                                     &blocked_candidate, kDescriptorDistanceHigh);
    if (back != static_cast<int>(k)) continue;
    (*matched)[j] = candidate_points[k];
    blocked_current[j] = blocked_candidate[k] = true;
    ++added;
  }
  return added;
}

// The points of the loop keyframe and its covisible keyframes, each once, in id order of the
// keyframes.
std::vector<MapPoint*> LoopPoints(KeyFrame* loop) {
  std::vector<KeyFrame*> keyframes = loop->covisible_keyframes();
  keyframes.push_back(loop);
  std::set<MapPoint*, MapPointIdLess> seen;
  std::vector<MapPoint*> points;
  for (KeyFrame* keyframe : keyframes) {
    if (keyframe->is_bad()) continue;
    for (MapPoint* point : keyframe->valid_map_points())
      if (seen.insert(point).second) points.push_back(point);
  }
  return points;
}

int CountMatched(const std::vector<MapPoint*>& matched) {
  int count = 0;
  for (MapPoint* point : matched) count += point != nullptr ? 1 : 0;
  return count;
}

// Keeps only the matched entries of the pairs flagged in `keep`.
std::vector<MapPoint*> KeepPairs(const std::vector<MapPoint*>& matched, const MatchPairs& pairs,
                                 const std::vector<bool>& keep) {
  std::vector<MapPoint*> kept(matched.size(), nullptr);
  for (std::size_t i = 0; i < pairs.pairs.size(); ++i)
    if (keep[i]) kept[pairs.current_index[i]] = matched[pairs.current_index[i]];
  return kept;
}

}  // namespace

bool VerifyLoopCandidate(KeyFrame* current, KeyFrame* candidate, const PlaceRecognition& places,
                         const LoopVerificationOptions& options, std::uint32_t seed, LoopMatch* match) {
  *match = LoopMatch();
  match->current = current;
  match->loop = candidate;
  std::vector<MapPoint*> matched = MatchByBow(current, candidate, places, options.bow);
  match->bow_matches = CountMatched(matched);
  if (match->bow_matches < options.min_bow_matches) return false;

  const PinholeCamera& camera = current->rig().camera;
  const PinholeCamera& candidate_camera = candidate->rig().camera;
  const MatchPairs bow_pairs = BuildPairs(*current, *candidate, matched);
  RigidRansacOptions ransac = options.ransac;
  ransac.seed = seed;
  const RigidRansacResult estimate = EstimateRigidRansac(bow_pairs.pairs, ransac, &camera, &candidate_camera);
  match->ransac_inliers = estimate.num_inliers;
  if (!estimate.success) return false;

  // RANSAC inliers plus guided matches, refined together.
  matched = KeepPairs(matched, bow_pairs, estimate.inliers);
  Rigid3 current_from_loop = estimate.a_from_b.rigid;
  GuidedMutualMatches(current, candidate, current_from_loop, options.guided_radius_px, &matched);
  const MatchPairs pairs = BuildPairs(*current, *candidate, matched);
  std::vector<bool> inliers;
  match->refined_inliers =
      RefineRelativePose(pairs.pairs, camera, candidate_camera, options.refinement, &current_from_loop, &inliers);
  if (match->refined_inliers < options.min_refined_inliers) return false;
  matched = KeepPairs(matched, pairs, inliers);

  // The loop points projected with the corrected pose complete the matches.
  match->current_from_loop = current_from_loop;
  match->corrected_cam_from_world = current_from_loop * candidate->cam_from_world();
  match->loop_points = LoopPoints(candidate);
  SearchByProjection(*current, match->corrected_cam_from_world, match->loop_points, options.projection_radius_factor,
                     &matched);
  match->total_matches = CountMatched(matched);
  match->matched_points = std::move(matched);
  return match->total_matches >= options.min_total_matches;
}

}  // namespace esdslam
