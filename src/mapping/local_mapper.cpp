#include "mapping/local_mapper.h"

#include <algorithm>

#include "common/error.h"
#include "map/keyframe.h"

namespace esdslam {

void LocalMapperOptions::Check() const {
  if (queue_capacity < 1) throw Error("local mapping: queue_capacity must be >= 1");
  if (triangulation_neighbours < 1) throw Error("local mapping: triangulation_neighbours must be >= 1");
  if (!(fuse_radius_factor > 0)) throw Error("local mapping: fuse_radius_factor must be positive");
  if (!(recent_culling.min_found_ratio >= 0 && recent_culling.min_found_ratio <= 1))
    throw Error("local mapping: min_found_ratio must be in [0, 1]");
  if (!(redundant_culling.redundant_ratio > 0 && redundant_culling.redundant_ratio <= 1))
    throw Error("local mapping: redundant_ratio must be in (0, 1]");
  bundle_adjustment.Check();
}

LocalMapper::LocalMapper(Map* map, const LocalMapperOptions& options, bool threaded)
    : map_(map),
      options_(options),
      threaded_(threaded),
      worker_("local mapping", ThreadedOrInline(threaded), static_cast<std::size_t>(std::max(1, options.queue_capacity)),
              [this](KeyFrame* keyframe) { HandleKeyFrame(keyframe); }) {
  options_.Check();
}

LocalMapper::~LocalMapper() {
  try {
    Close();
  } catch (...) {
  }
}

void LocalMapper::Start() { worker_.Start(); }

bool LocalMapper::AcceptsKeyFrames() const { return !threaded_ || in_flight_ == 0; }
int LocalMapper::QueuedKeyFrames() const { return static_cast<int>(worker_.Queued()); }

bool LocalMapper::ReserveKeyFrame() {
  std::lock_guard<std::mutex> lock(pause_mutex_);
  if (pause_requests_ > 0) return false;
  ++reserved_;
  in_flight_ = ++in_flight_locked_;
  return true;
}

void LocalMapper::InsertKeyFrame(KeyFrame* keyframe) {
  abort_ba_ = true;
  {
    std::lock_guard<std::mutex> lock(pause_mutex_);
    if (reserved_ > 0) --reserved_;
    else in_flight_ = ++in_flight_locked_;
  }
  bool queued = false;
  try {
    queued = worker_.Push(keyframe);
  } catch (const Error&) {
    FinishKeyFrame();  // local mapping failed: this keyframe never comes
    throw;
  }
  if (!queued) {
    FinishKeyFrame();
    throw Error("local mapping: keyframe inserted after Close()");
  }
}

void LocalMapper::FinishKeyFrame() {
  std::lock_guard<std::mutex> lock(pause_mutex_);
  in_flight_ = --in_flight_locked_;
  pause_cv_.notify_all();
}

void LocalMapper::Pause() {
  if (!threaded_) {
    // Synchronous mode: the caller's thread is the mapping thread; finish the queue now.
    ProcessQueued();
    std::lock_guard<std::mutex> lock(pause_mutex_);
    ++pause_requests_;
    return;
  }
  std::unique_lock<std::mutex> lock(pause_mutex_);
  ++pause_requests_;
  abort_ba_ = true;
  pause_cv_.wait(lock, [&] { return in_flight_locked_ == 0; });
}

void LocalMapper::Resume() {
  std::lock_guard<std::mutex> lock(pause_mutex_);
  if (pause_requests_ > 0) --pause_requests_;
}

void LocalMapper::ProcessQueued() {
  worker_.Drain();
  worker_.ThrowIfFailed();
}

void LocalMapper::Close(bool drop_pending) {
  if (drop_pending) drop_pending_ = true;
  worker_.Close();
}

void LocalMapper::HandleKeyFrame(KeyFrame* keyframe) {
  // Finished also when processing throws (the worker keeps the error), so that Pause returns.
  struct Finish {
    LocalMapper* mapper;
    ~Finish() { mapper->FinishKeyFrame(); }
  } finish{this};
  ProcessKeyFrame(keyframe);
}

bool LocalMapper::MoreWaiting() const { return QueuedKeyFrames() > 0 && !drop_pending_; }

// The table of contents of local mapping for one keyframe.
void LocalMapper::ProcessKeyFrame(KeyFrame* keyframe) {
  LocalMapperStats delta;
  {
    std::lock_guard<std::mutex> lock(map_->update_mutex());
    InsertKeyFrameIntoMap(map_, keyframe, &recent_points_);
    if (drop_pending_) return;
    delta.points_culled = CullRecentMapPoints(*keyframe, options_.recent_culling, &recent_points_);
    delta.points_created =
        CreateMapPointsFromNeighbours(map_, keyframe, options_.triangulation_neighbours, &recent_points_);
    if (!MoreWaiting()) FuseWithNeighbours(keyframe, options_.fuse_radius_factor);
  }
  abort_ba_ = false;
  if (!MoreWaiting() && options_.local_bundle_adjustment && map_->num_keyframes() > 2) {
    const BaSummary summary = LocalBundleAdjustment(map_, keyframe, options_.bundle_adjustment, &abort_ba_);
    delta.bundle_adjustments = 1;
    delta.bundle_adjustments_aborted = summary.aborted ? 1 : 0;
  }
  if (!MoreWaiting() && options_.keyframe_culling) {
    std::lock_guard<std::mutex> lock(map_->update_mutex());
    delta.keyframes_culled = CullRedundantKeyFrames(map_, keyframe, options_.redundant_culling);
  }
  if (downstream_ && !keyframe->is_bad()) downstream_(keyframe);
  std::lock_guard<std::mutex> lock(stats_mutex_);
  stats_.keyframes_processed += 1;
  stats_.points_created += delta.points_created;
  stats_.points_culled += delta.points_culled;
  stats_.keyframes_culled += delta.keyframes_culled;
  stats_.bundle_adjustments += delta.bundle_adjustments;
  stats_.bundle_adjustments_aborted += delta.bundle_adjustments_aborted;
}

LocalMapperStats LocalMapper::stats() const {
  std::lock_guard<std::mutex> lock(stats_mutex_);
  return stats_;
}

}  // namespace esdslam
