#include "loop/loop_closer.h"

#include <algorithm>
#include <cmath>

#include <spdlog/spdlog.h>

#include "common/error.h"
#include "common/timer.h"
#include "map/keyframe.h"

namespace esdslam {

void LoopClosingOptions::Check() const {
  if (min_keyframes_between_loops < 1) throw Error("loop closing: min_keyframes_between_loops must be >= 1");
  if (consistency_threshold < 1) throw Error("loop closing: consistency_threshold must be >= 1");
  verification.Check();
  if (!(fuse_radius_factor > 0)) throw Error("loop closing: fuse_radius_factor must be positive");
  if (essential_min_covisibility < 1) throw Error("loop closing: essential_min_covisibility must be >= 1");
  pose_graph.Check();
  global_ba.Check();
  if (queue_capacity < 1) throw Error("loop closing: queue_capacity must be >= 1");
}

LoopCloser::LoopCloser(Map* map, PlaceRecognition* places, MappingControl* mapping, const LoopClosingOptions& options,
                       bool threaded)
    : map_(map),
      places_(places),
      mapping_(mapping),
      options_(options),
      global_ba_(map, mapping, options.global_ba, threaded),
      consistency_(options.consistency_threshold),
      worker_("loop closing", ThreadedOrInline(threaded), static_cast<std::size_t>(std::max(1, options.queue_capacity)),
              [this](KeyFrame* keyframe) { ProcessKeyFrame(keyframe); }) {
  if (places_ == nullptr) throw Error("loop closing needs place recognition");
  options_.Check();
}

LoopCloser::~LoopCloser() {
  try {
    Close();
  } catch (const std::exception& e) {
    spdlog::error("loop closing: {}", e.what());
  }
}

void LoopCloser::Start() { worker_.Start(); }

void LoopCloser::InsertKeyFrame(KeyFrame* keyframe) {
  if (worker_.PushDropOldest(keyframe) != DropOldestPush::kQueuedDroppedOldest) return;
  std::lock_guard<std::mutex> lock(stats_mutex_);
  ++stats_.keyframes_dropped;
}

void LoopCloser::ProcessQueued() {
  worker_.Drain();
  worker_.ThrowIfFailed();
}

void LoopCloser::Close() {
  try {
    worker_.Close();
  } catch (const Error&) {
    global_ba_.Close();  // a running global BA is still finished (result merged) and joined
    throw;
  }
  global_ba_.Close();
}

LoopClosingStats LoopCloser::stats() const {
  LoopClosingStats copy;
  {
    std::lock_guard<std::mutex> lock(stats_mutex_);
    copy = stats_;
  }
  copy.global_ba = global_ba_.stats();
  return copy;
}

// The table of contents of loop closing for one keyframe.
void LoopCloser::ProcessKeyFrame(KeyFrame* keyframe) {
  if (keyframe->is_bad()) return;
  Stopwatch watch;
  const std::vector<KeyFrame*> candidates = DetectConsistentCandidates(keyframe);
  const double detect_ms = watch.ElapsedMs();
  watch.Restart();
  LoopMatch match;
  const bool verified = !candidates.empty() && VerifyCandidates(keyframe, candidates, &match);
  const double verify_ms = watch.ElapsedMs();
  watch.Restart();
  LoopEvent event;
  const bool closed = verified && CorrectLoop(match, &event);
  event.correct_ms = watch.ElapsedMs();
  {
    std::lock_guard<std::mutex> lock(stats_mutex_);
    ++stats_.keyframes_checked;
    stats_.consistent_candidates += static_cast<int>(candidates.size());
    stats_.loops_detected += verified ? 1 : 0;
    stats_.loops_closed += closed ? 1 : 0;
    stats_.detect_ms += detect_ms;
    stats_.verify_ms += verify_ms;
    if (closed) stats_.correct_ms += event.correct_ms, stats_.events.push_back(event);
  }
  if (closed && options_.global_bundle_adjustment) global_ba_.Start(keyframe->id());
}

std::vector<KeyFrame*> LoopCloser::DetectConsistentCandidates(KeyFrame* keyframe) {
  if (keyframe->id() < last_loop_keyframe_id_ + options_.min_keyframes_between_loops) return {};
  places_->AddKeyFrame(keyframe);  // no-op when tracking indexed it already
  std::vector<KeyFrame*> connected;
  for (const auto& [other, weight] : keyframe->connection_weights()) connected.push_back(other);
  const std::vector<KeyFrame*> candidates = places_->LoopCandidates(keyframe, keyframe->covisible_keyframes(), connected);
  std::vector<CandidateGroup> groups;
  for (KeyFrame* candidate : candidates) {
    CandidateGroup group{candidate->id(), {candidate->id()}};
    for (const auto& [other, weight] : candidate->connection_weights()) group.keyframes.insert(other->id());
    groups.push_back(std::move(group));
  }
  const std::vector<long> enough = consistency_.Update(groups);
  spdlog::debug("loop: keyframe {}: {} connected, {} BoW candidates{}, {} consistent", keyframe->id(), connected.size(),
                candidates.size(), candidates.empty() ? "" : fmt::format(" (best {})", candidates.front()->id()),
                enough.size());
  std::vector<KeyFrame*> consistent;
  for (const long id : enough)
    for (KeyFrame* candidate : candidates)
      if (candidate->id() == id) consistent.push_back(candidate);
  return consistent;
}

bool LoopCloser::VerifyCandidates(KeyFrame* keyframe, const std::vector<KeyFrame*>& candidates, LoopMatch* match) {
  for (KeyFrame* candidate : candidates) {
    const auto seed = static_cast<std::uint32_t>(options_.verification.ransac.seed + 7919 * keyframe->id() + candidate->id());
    const bool ok = VerifyLoopCandidate(keyframe, candidate, *places_, options_.verification, seed, match);
    spdlog::debug("loop: keyframe {} candidate {}: {} BoW matches, {} RANSAC inliers, {} refined, {} total -> {}",
                  keyframe->id(), candidate->id(), match->bow_matches, match->ransac_inliers, match->refined_inliers,
                  match->total_matches, ok ? "verified" : "rejected");
    if (ok) return true;
  }
  return false;
}

bool LoopCloser::CorrectLoop(const LoopMatch& match, LoopEvent* event) {
  global_ba_.Abort();  // outdated by this correction
  MappingPause pause(mapping_);
  std::lock_guard<std::mutex> lock(map_->update_mutex());
  KeyFrame* current = match.current;
  KeyFrame* loop = match.loop;
  if (current->is_bad() || loop->is_bad()) {
    spdlog::info("loop: keyframe {} or {} culled before the correction; loop dropped", current->id(), loop->id());
    return false;
  }
  current->UpdateConnections();
  const Rigid3 before = current->cam_from_world();
  // The loop keyframe may have moved (local BA) since verification: compose with its pose now.
  const Rigid3 corrected = match.current_from_loop * loop->cam_from_world();
  const GroupCorrection group = CorrectCurrentGroup(current, corrected);
  event->fused = FuseLoopMatches(current, match.matched_points);
  event->fused += FuseLoopPointsIntoGroup(group, match.loop_points, options_.fuse_radius_factor);
  const auto connections = NewLoopConnections(group);
  const EssentialGraphInput input{loop, current, &group, &connections, loop_edges_, options_.essential_min_covisibility};
  const EssentialGraphSummary graph = OptimizeEssentialGraph(map_, input, options_.pose_graph);
  loop_edges_.emplace_back(loop, current);
  last_loop_keyframe_id_ = current->id();
  event->current_id = current->id();
  event->loop_id = loop->id();
  event->timestamp = current->timestamp();
  event->loop_timestamp = loop->timestamp();
  event->inliers = match.refined_inliers;
  event->matches = match.total_matches;
  event->correction_m = (before.inverse().translation() - corrected.inverse().translation()).norm();
  event->correction_deg = RotationAngle(before.rotation() * corrected.rotation().conjugate()) * 180.0 / M_PI;
  spdlog::info("loop: closed keyframe {} -> {} ({} inliers, {} matches, {} fused, correction {:.3f} m / {:.2f} deg; "
               "essential graph {} keyframes, {} edges)",
               current->id(), loop->id(), event->inliers, event->matches, event->fused, event->correction_m,
               event->correction_deg, graph.keyframes, graph.edges);
  return true;
}

}  // namespace esdslam
