#pragma once
// Runs the global bundle adjustment after a loop correction on its own thread (a Worker, see
// common/worker.h, with room for one run; or, in synchronous mode, right away on the caller's
// thread): snapshot under Map::update_mutex, solve without locks (tracking and local mapping go
// on), then merge with local mapping paused and the update mutex held. A new loop correction
// aborts a running one (its result is dropped).
//
// Threads and locks: the runner's own mutex guards its statistics only; it is never held while
// taking Map::update_mutex or pausing local mapping. Start/Abort are called by the loop-closing
// thread only, Close by the owner once loop closing has stopped.

#include <atomic>
#include <mutex>

#include "common/worker.h"
#include "loop/global_bundle_adjustment.h"
#include "map/keyframe_sink.h"

namespace esdslam {

struct GlobalBaStats {
  int started = 0, completed = 0, aborted = 0;
  double total_ms = 0;        // snapshot + solve + merge of the completed ones
  double last_ms = 0;
  int last_keyframes = 0, last_points = 0;
};

class GlobalBaRunner {
 public:
  // `mapping` may be null (nothing to pause). Pointers are not owned.
  GlobalBaRunner(Map* map, MappingControl* mapping, const GlobalBundleAdjustmentOptions& options, bool threaded);
  ~GlobalBaRunner();  // aborts a running one
  GlobalBaRunner(const GlobalBaRunner&) = delete;
  GlobalBaRunner& operator=(const GlobalBaRunner&) = delete;

  // Starts a global BA for the loop closed at keyframe `loop_keyframe_id` (waits for a previous
  // one to finish first). Synchronous mode: runs it to the end before returning. Throws Error if
  // an earlier one failed.
  void Start(long loop_keyframe_id);
  // Stops a running one early (result dropped) and waits for it.
  void Abort();
  // Waits for a running one to finish (result merged) and joins the thread. Idempotent. Throws
  // Error if one failed.
  void Close();
  GlobalBaStats stats() const;

 private:
  void Run(long loop_keyframe_id);

  Map* map_;
  MappingControl* mapping_;
  GlobalBundleAdjustmentOptions options_;
  std::atomic<bool> stop_{false};
  mutable std::mutex mutex_;  // stats_
  GlobalBaStats stats_;
  Worker<long> worker_;  // loop keyframe ids; last: stopped before the state its handler uses
};

}  // namespace esdslam
