#include "loop/global_ba_runner.h"

#include <spdlog/spdlog.h>

#include "common/error.h"
#include "common/timer.h"

namespace esdslam {

GlobalBaRunner::GlobalBaRunner(Map* map, MappingControl* mapping, const GlobalBundleAdjustmentOptions& options,
                               bool threaded)
    : map_(map),
      mapping_(mapping),
      options_(options),
      worker_("global bundle adjustment", ThreadedOrInline(threaded), 1, [this](long id) { Run(id); }) {
  options_.Check();
  worker_.Start();
}

GlobalBaRunner::~GlobalBaRunner() { stop_ = true; }  // the worker then finishes it early and joins

void GlobalBaRunner::Start(long loop_keyframe_id) {
  worker_.Drain();
  stop_ = false;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ++stats_.started;
  }
  worker_.Push(loop_keyframe_id);
  if (!worker_.threaded()) worker_.Drain();
}

void GlobalBaRunner::Abort() {
  stop_ = true;
  worker_.Drain();
}

void GlobalBaRunner::Close() { worker_.Close(); }

GlobalBaStats GlobalBaRunner::stats() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return stats_;
}

// The table of contents of one global BA.
void GlobalBaRunner::Run(long loop_keyframe_id) {
  Stopwatch watch;
  GlobalBaSnapshot snapshot;
  {
    std::lock_guard<std::mutex> lock(map_->update_mutex());
    snapshot = BuildGlobalBundleAdjustment(*map_);
  }
  const BaSummary solve = SolveGlobalBundleAdjustment(options_, &snapshot, &stop_);
  if (solve.aborted || stop_) {
    spdlog::info("loop: global BA after loop at keyframe {} aborted", loop_keyframe_id);
    std::lock_guard<std::mutex> lock(mutex_);
    ++stats_.aborted;
    return;
  }
  GlobalBaMergeSummary merge;
  {
    MappingPause pause(mapping_);
    std::lock_guard<std::mutex> lock(map_->update_mutex());
    merge = MergeGlobalBundleAdjustment(map_, snapshot);
  }
  const double ms = watch.ElapsedMs();
  spdlog::info("loop: global BA after loop at keyframe {}: {} keyframes, {} points, cost {:.4g} -> {:.4g}, "
               "{} keyframes / {} points created meanwhile corrected, {:.0f} ms",
               loop_keyframe_id, merge.keyframes_solved, merge.points_solved, solve.initial_cost, solve.final_cost,
               merge.keyframes_propagated, merge.points_propagated, ms);
  std::lock_guard<std::mutex> lock(mutex_);
  ++stats_.completed;
  stats_.total_ms += ms;
  stats_.last_ms = ms;
  stats_.last_keyframes = merge.keyframes_solved;
  stats_.last_points = merge.points_solved;
}

}  // namespace esdslam
