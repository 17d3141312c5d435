#pragma once
// Projection matching of map points into a keyframe with a given (corrected) pose, as loop
// closing needs it (ORB-SLAM2's ORBmatcher::SearchByProjection / Fuse with a Sim3, the scale
// fixed): the point must project inside the image, lie within its scale-invariance distance
// range and be seen within 60 degrees of its mean viewing direction; the keypoints searched lie
// within radius_factor x scale(predicted level) px of the projection, at the predicted level or
// one below, and the best Hamming distance must be <= TH_LOW (50). Dynamic keypoints are never
// matched. Reads objects through their own locks only.

#include <utility>
#include <vector>

#include "common/geometry.h"
#include "map/map_types.h"

namespace esdslam {

// Best keypoint of `keyframe` for `point` seen from `cam_from_world`; -1 when none qualifies.
// Keypoints with blocked[i] are skipped (blocked may be null: none is). max_distance: Hamming.
int ProjectionMatch(const KeyFrame& keyframe, const Rigid3& cam_from_world, const MapPoint& point, double radius_factor,
                    const std::vector<bool>* blocked = nullptr, int max_distance = 50);

// For each point (live, not already in *matched) finds a free keypoint of `keyframe` and stores
// it in (*matched)[keypoint]. Returns the matches added.
int SearchByProjection(const KeyFrame& keyframe, const Rigid3& cam_from_world, const std::vector<MapPoint*>& points,
                       double radius_factor, std::vector<MapPoint*>* matched);

struct LoopFuseResult {
  int observations_added = 0;
  // (point of the keyframe, loop point that takes it over): to be applied with
  // first->Replace(second) after the search (the caller holds Map::update_mutex).
  std::vector<std::pair<MapPoint*, MapPoint*>> replacements;
};
// Projects the loop points into `keyframe` (its current, corrected pose). A point matched to a
// keypoint without a live map point becomes observed there; one matched to a keypoint that holds
// another point is listed for replacement. Points the keyframe already observes are skipped.
LoopFuseResult FuseLoopPoints(KeyFrame* keyframe, const std::vector<MapPoint*>& loop_points, double radius_factor);

}  // namespace esdslam
