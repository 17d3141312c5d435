#pragma once
// The loop-closing thread (ORB-SLAM2's LoopClosing), fed by local mapping with every keyframe it
// finished. Per keyframe:
//   detection     BoW candidates scored against the keyframe's covisible neighbours, then the
//                 covisibility-consistency test over consecutive keyframes (loop_consistency.h);
//   verification  BoW matching + rigid RANSAC + guided matching + refinement + projection of
//                 the loop points (loop_verification.h), the first candidate passing wins;
//   correction    local mapping paused, Map::update_mutex held: current group corrected, loop
//                 points fused, essential-graph optimisation (loop_correction.h);
//   global BA     in its own thread (global_ba_runner.h), aborted by the next correction.
// The keyframes go through a Worker (common/worker.h). Threaded mode: Start() launches its
// thread. Synchronous mode: InsertKeyFrame only queues, the owner calls ProcessQueued() on its
// thread (the global BA then runs there too): runs repeat exactly. A failure is reported by the
// next InsertKeyFrame, ProcessQueued and Close.
//
// Shared data: the worker's queue (its own mutex), statistics (stats_mutex_). Detection and verification
// read map objects through their per-object locks without Map::update_mutex (local mapping and
// tracking go on); the keyframes involved are re-checked under the lock before correcting.
// Lock order: MappingControl::Pause -> Map::update_mutex -> per-object locks; stats_mutex_ is
// a leaf.

#include <memory>
#include <mutex>
#include <utility>
#include <vector>

#include "common/worker.h"
#include "loop/global_ba_runner.h"
#include "loop/loop_consistency.h"
#include "loop/loop_correction.h"
#include "loop/loop_verification.h"
#include "place/place_recognition.h"
#include "map/keyframe_sink.h"

namespace esdslam {

struct LoopClosingOptions {
  int min_keyframes_between_loops = 10;  // no detection in the first 10 keyframes / 10 after a loop
  int consistency_threshold = 3;         // consecutive consistent keyframes (ORB-SLAM2: 3)
  LoopVerificationOptions verification;
  double fuse_radius_factor = 4;         // loop fusion window x level scale (ORB-SLAM2: 4)
  int essential_min_covisibility = 100;  // covisibility edges of the essential graph
  PoseGraphOptions pose_graph;
  bool global_bundle_adjustment = true;
  GlobalBundleAdjustmentOptions global_ba;
  int queue_capacity = 64;  // keyframes waiting; when full the oldest is dropped (never blocks)
  void Check() const;
};

struct LoopEvent {
  long current_id = -1, loop_id = -1;  // keyframe ids
  double timestamp = 0;                // of the current keyframe
  double loop_timestamp = 0;           // of the loop keyframe
  int inliers = 0, matches = 0, fused = 0;
  double correction_m = 0, correction_deg = 0;  // how far the current keyframe moved
  double correct_ms = 0;
};

struct LoopClosingStats {
  int keyframes_checked = 0;
  int consistent_candidates = 0;  // candidates that reached geometric verification
  int loops_detected = 0;         // verified
  int loops_closed = 0;           // corrected
  int keyframes_dropped = 0;      // queue overflow
  double detect_ms = 0, verify_ms = 0, correct_ms = 0;  // totals
  std::vector<LoopEvent> events;
  GlobalBaStats global_ba;
};

class LoopCloser {
 public:
  // Not owned; `mapping` may be null (nothing to pause). All must outlive the loop closer.
  LoopCloser(Map* map, PlaceRecognition* places, MappingControl* mapping, const LoopClosingOptions& options,
             bool threaded);
  ~LoopCloser();
  LoopCloser(const LoopCloser&) = delete;
  LoopCloser& operator=(const LoopCloser&) = delete;

  void Start();
  // From local mapping; never blocks: when queue_capacity keyframes wait, the oldest is dropped.
  // Ignored after Close(). Throws Error when loop closing failed.
  void InsertKeyFrame(KeyFrame* keyframe);
  // Synchronous mode: processes the queued keyframes now (the caller must not hold the map lock);
  // threaded mode: waits until they are processed. Throws Error when loop closing failed.
  void ProcessQueued();
  // Processes every queued keyframe, waits for the global BA and joins. Idempotent. Throws Error
  // when processing failed.
  void Close();
  LoopClosingStats stats() const;

 private:
  void ProcessKeyFrame(KeyFrame* keyframe);
  std::vector<KeyFrame*> DetectConsistentCandidates(KeyFrame* keyframe);
  bool VerifyCandidates(KeyFrame* keyframe, const std::vector<KeyFrame*>& candidates, LoopMatch* match);
  bool CorrectLoop(const LoopMatch& match, LoopEvent* event);

  Map* map_;
  PlaceRecognition* places_;
  MappingControl* mapping_;
  LoopClosingOptions options_;
  GlobalBaRunner global_ba_;
  // Worker-owned state.
  LoopConsistency consistency_;
  long last_loop_keyframe_id_ = 0;
  std::vector<std::pair<KeyFrame*, KeyFrame*>> loop_edges_;  // (loop, current) of closed loops
  mutable std::mutex stats_mutex_;
  LoopClosingStats stats_;
  Worker<KeyFrame*> worker_;  // last: stopped before the state its handler uses
};

}  // namespace esdslam
