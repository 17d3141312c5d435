#pragma once
// Global bundle adjustment after a loop correction (ORB-SLAM2's RunGlobalBundleAdjustment):
// every live keyframe (the first one fixed) and every live point, solved on a snapshot without
// any lock while tracking and local mapping go on, then merged back. Keyframes created while it
// ran get the correction of their spanning-tree parent (their pose relative to the parent is
// kept); points created meanwhile move with their reference keyframe.
//   Build:  caller holds Map::update_mutex.
//   Solve:  no lock; `stop` aborts (the result is then dropped).
//   Merge:  caller holds Map::update_mutex with local mapping paused.

#include <atomic>
#include <map>
#include <vector>

#include "map/map.h"
#include "optim/bundle_adjustment.h"

namespace esdslam {

struct GlobalBundleAdjustmentOptions {
  int iterations = 10;  // Levenberg-Marquardt iterations with the Huber loss (ORB-SLAM2: 10)
  void Check() const;
};

struct GlobalBaSnapshot {
  std::vector<KeyFrame*> keyframes;  // problem.keyframes[i] <-> keyframes[i]
  std::vector<MapPoint*> points;     // problem.points[i] <-> points[i]
  BaProblem problem;
};

GlobalBaSnapshot BuildGlobalBundleAdjustment(const Map& map);
BaSummary SolveGlobalBundleAdjustment(const GlobalBundleAdjustmentOptions& options, GlobalBaSnapshot* snapshot,
                                      const std::atomic<bool>* stop);

// Pure: new poses for a spanning forest (parent_of: child id -> parent id; roots have none) where
// `optimized` holds the solved poses of some nodes. Walking down from the roots, a node without a
// solved pose keeps its pose relative to its parent: T' = (T * T_parent^-1) * T_parent'.
// Nodes whose ancestors all lack solved poses keep their pose. Returns every node of
// cam_from_world.
std::map<long, Rigid3> PropagateThroughSpanningTree(const std::map<long, Rigid3>& cam_from_world,
                                                    const std::map<long, long>& parent_of,
                                                    const std::map<long, Rigid3>& optimized);

struct GlobalBaMergeSummary {
  int keyframes_solved = 0;      // took the BA result
  int keyframes_propagated = 0;  // created meanwhile, corrected through the spanning tree
  int points_solved = 0;
  int points_propagated = 0;
};
GlobalBaMergeSummary MergeGlobalBundleAdjustment(Map* map, const GlobalBaSnapshot& solved);

}  // namespace esdslam
