#pragma once
// Builds the static dense map off the tracking thread. Keyframes (colour, depth, dynamic mask)
// go through a Worker (common/worker.h) to its thread, which back-projects them into the DenseMap;
// tracking only pays for the hand-off (a queue push of shared images), so its time does not grow
// with the map.
//
// Poses: `poses` (optional) returns the current world_from_cam of the keyframes handed over, e.g.
// read from the SLAM map after bundle adjustment or loop closure (culled keyframes through their
// spanning-tree parent). The worker calls it before integrating each keyframe, so points merge at
// up-to-date poses; on-demand builds call it too. Without a source, hand-off poses are used.
//
// Errors: a keyframe that fails is logged and the worker goes on with the next; the first error
// is rethrown by the next AddKeyframe and by Finish.
//
// Threads and locks: producers call AddKeyframe; the worker pops the queue; any thread may call
// the on-demand methods (CurrentPoses, CurrentCloud, WriteOutputs, stats) at any time, also
// while the worker runs (they see the keyframes integrated so far). The pose source is always
// called with no DenseMapper/DenseMap lock held (it may take the SLAM map's update mutex); the
// queue and the DenseMap each have their own lock, never held together.

#include <functional>
#include <mutex>
#include <string>

#include "common/worker.h"
#include "dense/dense_map.h"
#include "dense/dense_outputs.h"

namespace esdslam {

// Must be thread-safe: called from the worker and from on-demand callers.
using KeyframePoseSource = std::function<KeyframePoses()>;

struct DenseMapperOptions {
  bool threaded = true;             // false: each keyframe is processed on the caller's thread (deterministic)
  std::size_t queue_capacity = 16;  // keyframes waiting; AddKeyframe blocks when full (back-pressure)
  std::string mask_dir;             // set: the worker writes each keyframe's dynamic mask as <timestamp>.png
};

struct DenseMapperStats {
  long keyframes = 0;
  double mean_keyframe_ms = 0;  // poses + back-projection + re-indexing + integration, per keyframe
  double max_keyframe_ms = 0;
  double mean_pose_ms = 0;      // of which reading the poses (waits for the SLAM map's update mutex)
  double mean_keyframe_cpu_ms = 0;  // CPU time of the same work (wall time also counts waiting for a core)
  double mean_handoff_ms = 0;   // AddKeyframe on the producer's thread (queue push; waits only when full)
  double max_handoff_ms = 0;
  DenseMapStats map;
};

class DenseMapper {
 public:
  DenseMapper(const PinholeCamera& camera, const DenseOptions& options, KeyframePoseSource poses = {},
              const DenseMapperOptions& mapper_options = {});
  ~DenseMapper();
  DenseMapper(const DenseMapper&) = delete;
  DenseMapper& operator=(const DenseMapper&) = delete;

  // Threaded: queues the keyframe (blocks while queue_capacity wait); otherwise integrates it now.
  // Throws Error when an earlier keyframe failed.
  void AddKeyframe(DenseKeyframe keyframe);
  // Waits until every queued keyframe is in the map and stops the worker. Idempotent. Throws
  // Error when a keyframe failed (the others are in the map).
  void Finish();

  // On demand (any thread, any time): the current poses (source, else hand-off), the global cloud
  // at them, and all output files at them.
  KeyframePoses CurrentPoses() const;
  PointCloud CurrentCloud() const;
  DenseOutputSummary WriteOutputs(const std::string& dir, const DenseOutputFiles& files = {}) const;

  DenseMapperStats stats() const;
  const DenseMap& map() const { return map_; }

 private:
  void Process(const DenseKeyframe& keyframe);

  DenseMap map_;
  KeyframePoseSource poses_;
  DenseMapperOptions mapper_options_;
  mutable std::mutex stats_mutex_;
  double total_ms_ = 0, max_ms_ = 0, pose_ms_ = 0, cpu_ms_ = 0;
  long processed_ = 0;
  double handoff_total_ms_ = 0, handoff_max_ms_ = 0;
  long handoffs_ = 0;
  Worker<DenseKeyframe> worker_;  // last: stopped before the state its handler uses
};

}  // namespace esdslam
