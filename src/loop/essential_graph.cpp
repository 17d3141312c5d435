// Loop correction step 4: pose-graph optimisation over the essential graph (loop_correction.h).
#include <spdlog/spdlog.h>

#include "loop/loop_correction.h"
#include "map/keyframe.h"
#include "map/map_point.h"

namespace esdslam {
namespace {

using PairSet = std::set<std::pair<long, long>>;

std::pair<long, long> Ordered(long a, long b) { return {std::min(a, b), std::max(a, b)}; }

struct GraphPoses {
  std::map<long, Rigid3> initial;  // current poses (the group already corrected)
  std::map<long, Rigid3> measure;  // poses the old edges are measured with (group: before correction)
};

GraphPoses CollectPoses(const std::vector<KeyFrame*>& keyframes, const GroupCorrection& correction) {
  GraphPoses poses;
  for (KeyFrame* keyframe : keyframes) {
    poses.initial[keyframe->id()] = keyframe->cam_from_world();
    const auto it = correction.non_corrected.find(keyframe);
    poses.measure[keyframe->id()] = it != correction.non_corrected.end() ? it->second : poses.initial[keyframe->id()];
  }
  return poses;
}

// The new links across the loop, measured with the corrected poses: the current-loop link
// always, the others when they share >= min_covisibility points.
std::vector<PoseGraphEdge> LoopConnectionEdges(const EssentialGraphInput& input, const GraphPoses& poses,
                                               PairSet* linked) {
  std::vector<PoseGraphEdge> edges;
  for (const auto& [keyframe, connected] : *input.loop_connections) {
    for (KeyFrame* other : connected) {
      const bool main_link = keyframe == input.current && other == input.loop;
      if (!main_link && keyframe->Weight(other) < input.min_covisibility) continue;
      if (!poses.initial.count(keyframe->id()) || !poses.initial.count(other->id())) continue;
      if (!linked->insert(Ordered(keyframe->id(), other->id())).second) continue;
      edges.push_back(RelativePoseEdge(keyframe->id(), other->id(), poses.initial.at(keyframe->id()),
                                       poses.initial.at(other->id())));
    }
  }
  return edges;
}

// Spanning tree, earlier loop edges and strong covisibility links (not the new loop links),
// measured with the poses before the correction.
std::vector<PoseGraphEdge> OldEdges(const std::vector<KeyFrame*>& keyframes, const EssentialGraphInput& input,
                                    const GraphPoses& poses, const PairSet& new_links) {
  std::map<long, long> parent_of;
  std::vector<CovisibilityLink> covisibility;
  for (KeyFrame* keyframe : keyframes) {
    KeyFrame* parent = keyframe->parent();
    if (parent != nullptr && !parent->is_bad()) parent_of[keyframe->id()] = parent->id();
    for (const auto& [other, weight] : keyframe->connection_weights())
      if (other->id() > keyframe->id() && !new_links.count(Ordered(keyframe->id(), other->id())))
        covisibility.push_back({keyframe->id(), other->id(), weight});
  }
  std::vector<PoseGraphEdge> loop_edges;
  for (auto [a, b] : input.previous_loop_edges) {
    Rigid3 unused;
    a = LiveAncestor(a, &unused), b = LiveAncestor(b, &unused);
    if (a == nullptr || b == nullptr || a == b || !poses.measure.count(a->id()) || !poses.measure.count(b->id())) continue;
    loop_edges.push_back(RelativePoseEdge(a->id(), b->id(), poses.measure.at(a->id()), poses.measure.at(b->id())));
  }
  return EssentialGraphEdges(poses.measure, parent_of, covisibility, loop_edges, input.min_covisibility);
}

// Moves every live point with its reference keyframe (or the group keyframe that corrected it):
// p' = T_ref'^-1 * T_ref * p.
int MovePoints(const Map& map, const GroupCorrection& correction, const std::map<long, Rigid3>& before,
               const std::map<long, Rigid3>& after) {
  int moved = 0;
  for (MapPoint* point : map.map_points()) {
    if (point->is_bad()) continue;
    const auto corrector = correction.corrected_by.find(point);
    KeyFrame* reference = corrector != correction.corrected_by.end() ? corrector->second : point->reference_keyframe();
    if (reference == nullptr) continue;
    const auto old_it = before.find(reference->id()), new_it = after.find(reference->id());
    if (old_it == before.end() || new_it == after.end()) continue;
    point->set_position(new_it->second.inverse() * (old_it->second * point->position()));
    point->UpdateNormalAndDepth();
    ++moved;
  }
  return moved;
}

}  // namespace

EssentialGraphSummary OptimizeEssentialGraph(Map* map, const EssentialGraphInput& input,
                                             const PoseGraphOptions& options) {
  EssentialGraphSummary summary;
  std::vector<KeyFrame*> keyframes;
  for (KeyFrame* keyframe : map->keyframes())
    if (!keyframe->is_bad()) keyframes.push_back(keyframe);
  const GraphPoses poses = CollectPoses(keyframes, *input.correction);
  PairSet new_links;
  std::vector<PoseGraphEdge> edges = LoopConnectionEdges(input, poses, &new_links);
  const std::vector<PoseGraphEdge> old_edges = OldEdges(keyframes, input, poses, new_links);
  edges.insert(edges.end(), old_edges.begin(), old_edges.end());
  summary.keyframes = static_cast<int>(keyframes.size());
  summary.edges = static_cast<int>(edges.size());
  summary.result = OptimizePoseGraph(poses.initial, edges, {input.loop->id()}, options);
  double max_move = 0, sum_move = 0;
  for (KeyFrame* keyframe : keyframes) {
    const Rigid3& after = summary.result.cam_from_world.at(keyframe->id());
    const double move = (after.inverse().translation() - poses.initial.at(keyframe->id()).inverse().translation()).norm();
    max_move = std::max(max_move, move), sum_move += move;
    keyframe->set_cam_from_world(after);
  }
  spdlog::debug("loop: essential graph moved keyframes by {:.4f} m on average, {:.4f} m at most",
                sum_move / std::max<std::size_t>(1, keyframes.size()), max_move);
  summary.points_moved = MovePoints(*map, *input.correction, poses.initial, summary.result.cam_from_world);
  spdlog::debug("loop: essential graph {} keyframes, {} edges, cost {:.3g} -> {:.3g}", summary.keyframes,
                summary.edges, summary.result.initial_cost, summary.result.final_cost);
  return summary;
}

}  // namespace esdslam
