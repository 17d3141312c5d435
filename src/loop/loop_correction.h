#pragma once
// Loop correction (ORB-SLAM2's LoopClosing::CorrectLoop with the scale fixed), as steps on the
// map so that tests can run them one by one. Unless stated otherwise the caller holds
// Map::update_mutex() and local mapping is paused.
//   1. CorrectCurrentGroup: the current keyframe takes the pose that agrees with the loop
//      keyframe; its covisible keyframes keep their pose relative to it; the points they see
//      move rigidly with the keyframe that corrects them;
//   2. FuseLoopMatches / FuseLoopPointsIntoGroup: duplicated points (the same landmark mapped
//      before and after the drift) are merged, the loop side surviving;
//   3. NewLoopConnections: covisibility links the fusion created across the loop;
//   4. OptimizeEssentialGraph: pose graph over the spanning tree, strong covisibility edges
//      (>= 100 shared points), earlier loop edges and the new loop links, the loop keyframe
//      fixed; every point then moves with its reference keyframe.

#include <map>
#include <set>
#include <utility>
#include <vector>

#include "loop/pose_graph.h"
#include "map/map.h"

namespace esdslam {

// Pure: poses of a group whose member `current` moves from current_cam_from_world to
// current_corrected, every member keeping its pose relative to it:
//   T_i' = (T_i * T_current^-1) * T_current'   (T = cam_from_world).
std::map<long, Rigid3> PropagateCorrection(const Rigid3& current_cam_from_world, const Rigid3& current_corrected,
                                           const std::map<long, Rigid3>& group_cam_from_world);

struct GroupCorrection {
  std::vector<KeyFrame*> group;  // the current keyframe and its covisible keyframes, id order
  std::map<KeyFrame*, Rigid3, KeyFrameIdLess> non_corrected;  // cam_from_world before
  std::map<KeyFrame*, Rigid3, KeyFrameIdLess> corrected;      // cam_from_world after
  // Each moved point and the group keyframe whose correction moved it.
  std::map<MapPoint*, KeyFrame*, MapPointIdLess> corrected_by;
};

// Step 1. Sets the group's poses and moves their points (each once, by the first group keyframe
// in id order that sees it); updates the points' normals and distances.
GroupCorrection CorrectCurrentGroup(KeyFrame* current, const Rigid3& current_corrected);

// Step 2a. matched_points[i] (a loop point matched to the current keyframe's keypoint i) takes
// over the current keyframe's point there, or becomes observed at i. Returns the points fused.
int FuseLoopMatches(KeyFrame* current, const std::vector<MapPoint*>& matched_points);
// Step 2b. Projects the loop points into every group keyframe (corrected poses) and fuses them
// (radius_factor x level scale px). Returns observations added + points replaced.
int FuseLoopPointsIntoGroup(const GroupCorrection& correction, const std::vector<MapPoint*>& loop_points,
                            double radius_factor);

// Step 3. Updates the group's connections and returns, per group keyframe, the keyframes it is
// now connected to that were neither its covisible keyframes before nor group members.
std::map<KeyFrame*, std::set<KeyFrame*, KeyFrameIdLess>, KeyFrameIdLess> NewLoopConnections(
    const GroupCorrection& correction);

struct EssentialGraphInput {
  KeyFrame* loop = nullptr;     // fixed
  KeyFrame* current = nullptr;
  const GroupCorrection* correction = nullptr;
  const std::map<KeyFrame*, std::set<KeyFrame*, KeyFrameIdLess>, KeyFrameIdLess>* loop_connections = nullptr;
  std::vector<std::pair<KeyFrame*, KeyFrame*>> previous_loop_edges;  // earlier closed loops
  int min_covisibility = 100;
};

struct EssentialGraphSummary {
  int keyframes = 0;
  int edges = 0;
  int points_moved = 0;
  PoseGraphResult result;  // poses by keyframe id
};

// Step 4. Edges are measured with the poses before the correction (the group's non-corrected
// poses), the new loop links with the corrected ones; the optimised poses are written to the
// keyframes and each live point moves with its reference keyframe (or the group keyframe that
// corrected it in step 1).
EssentialGraphSummary OptimizeEssentialGraph(Map* map, const EssentialGraphInput& input,
                                             const PoseGraphOptions& options);

}  // namespace esdslam
