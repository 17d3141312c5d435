#pragma once
// The steps of local mapping (ORB-SLAM2's LocalMapping), as functions on the map so that tests can
// run them one by one. Unless stated otherwise the caller holds Map::update_mutex().

#include <atomic>
#include <mutex>
#include <vector>

#include "map/map.h"
#include "optim/bundle_adjustment.h"

namespace esdslam {

// Adds the keyframe to the map: observations of its associated points (points it created itself
// already have them and go to `recent_points`), descriptors/normals, covisibility, spanning tree.
void InsertKeyFrameIntoMap(Map* map, KeyFrame* keyframe, std::vector<MapPoint*>* recent_points);

struct RecentPointCulling {
  double min_found_ratio = 0.25;  // found / visible in tracking
  int min_observations = 3;       // ORB-SLAM2 weighted count (2 per view with depth): cull if <=
  int keyframes_before_check = 2; // ... once this many keyframes passed since creation
  int keyframes_until_kept = 3;   // points older than this leave the recent list
};
// Culls recent points with a low found ratio or too few observations; returns points culled.
int CullRecentMapPoints(const KeyFrame& current, const RecentPointCulling& options,
                        std::vector<MapPoint*>* recent_points);

// Matches the keyframe's unassociated keypoints with those of its best covisible neighbours
// (depth-guided projection for keypoints with depth, epipolar search otherwise), triangulates (or
// uses the measured depth when parallax is small), checks reprojection and scale consistency and
// creates map points (appended to `recent_points`). Returns points created.
int CreateMapPointsFromNeighbours(Map* map, KeyFrame* keyframe, int num_neighbours,
                                  std::vector<MapPoint*>* recent_points);

// Projects the keyframe's points into its neighbours (10 best covisible + 5 best of each) and the
// neighbours' points into the keyframe; merges duplicates (the point with more observations
// survives) and adds observations. Updates descriptors, normals and connections. Returns merges +
// added observations.
int FuseWithNeighbours(KeyFrame* keyframe, double radius_factor = 3.0);
// One direction of the above: fuses `points` into `keyframe`.
int FusePointsIntoKeyFrame(KeyFrame* keyframe, const std::vector<MapPoint*>& points, double radius_factor);

// Local BA over the keyframe and its covisible keyframes (optimised; the first keyframe stays
// fixed) and the points they see; keyframes that see those points but are not covisible are
// fixed. Locks `map->update_mutex()` itself to build the problem and to write back (the solve
// runs unlocked); the caller must NOT hold it. `stop` aborts the solve early.
BaSummary LocalBundleAdjustment(Map* map, KeyFrame* keyframe, const BundleAdjustmentOptions& options,
                                const std::atomic<bool>* stop);

struct RedundantKeyFrameCulling {
  double redundant_ratio = 0.9;  // culled when more than this share of its close points ...
  int min_other_observers = 3;   // ... is seen by this many other keyframes at the same or finer scale
};
// Culls covisible keyframes of `keyframe` (never the first one) that are redundant. Returns count.
int CullRedundantKeyFrames(Map* map, KeyFrame* keyframe, const RedundantKeyFrameCulling& options);

}  // namespace esdslam
