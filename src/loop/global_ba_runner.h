#pragma once
// Runs the global bundle adjustment after a loop correction in its own thread (or, in
// synchronous mode, right away on the caller's thread): snapshot under Map::update_mutex, solve
// without locks (tracking and local mapping go on), then merge with local mapping paused and the
// update mutex held. A new loop correction aborts a running one (its result is dropped).
//
// Threads and locks: the runner's own mutex guards its thread handle and statistics only; it is
// never held while taking Map::update_mutex or pausing local mapping. Start/Abort/Wait are called
// by the loop-closing thread only.

#include <atomic>
#include <mutex>
#include <string>
#include <thread>

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
  ~GlobalBaRunner();
  GlobalBaRunner(const GlobalBaRunner&) = delete;
  GlobalBaRunner& operator=(const GlobalBaRunner&) = delete;

  // Starts a global BA for the loop closed at keyframe `loop_keyframe_id` (waits for a previous
  // one to finish first). Synchronous mode: runs it to the end before returning.
  void Start(long loop_keyframe_id);
  // Stops a running one early (result dropped) and joins its thread.
  void Abort();
  // Waits for a running one to finish (result merged). Throws Error if it failed.
  void Wait();
  GlobalBaStats stats() const;

 private:
  void Run(long loop_keyframe_id);
  void Join();

  Map* map_;
  MappingControl* mapping_;
  GlobalBundleAdjustmentOptions options_;
  const bool threaded_;
  std::thread worker_;
  std::atomic<bool> stop_{false};
  mutable std::mutex mutex_;  // stats_, error_
  GlobalBaStats stats_;
  std::string error_;
};

}  // namespace esdslam
