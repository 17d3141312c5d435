#pragma once
// The local-mapping thread (ORB-SLAM2's LocalMapping): receives keyframes from tracking through a
// bounded queue and, for each, inserts it into the map, culls recent points, creates new points
// with its neighbours, fuses duplicates, runs local BA and culls redundant keyframes.
//
// The keyframes go through a Worker (common/worker.h): threaded mode runs them on its thread
// (Start()), synchronous mode only queues them and the owner calls ProcessQueued() on its own
// thread (deterministic runs and tests). Close() processes every queued keyframe (or, with
// drop_pending, only inserts them into the map without further work) and joins the worker.
// Each processed keyframe is handed to the downstream consumer (loop closing), if set. A failure
// is reported by the next InsertKeyFrame, ProcessQueued and Close; later keyframes are still
// processed, so the map stays usable.
//
// Pause (MappingControl, for loop closing and the global BA merge): new reservations are refused
// and Pause returns once every reserved or inserted keyframe has been processed; tracking creates
// no keyframe until Resume.

#include <atomic>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <vector>

#include "common/worker.h"
#include "map/keyframe_sink.h"
#include "map/map.h"
#include "mapping/mapping_steps.h"

namespace esdslam {

struct LocalMapperOptions {
  int queue_capacity = 8;
  int triangulation_neighbours = 10;  // best covisible keyframes used to create points (RGB-D: 10)
  double fuse_radius_factor = 3.0;
  bool local_bundle_adjustment = true;
  bool keyframe_culling = true;
  RecentPointCulling recent_culling;
  RedundantKeyFrameCulling redundant_culling;
  BundleAdjustmentOptions bundle_adjustment;
  void Check() const;
};

struct LocalMapperStats {
  int keyframes_processed = 0;
  int points_created = 0;
  int points_culled = 0;
  int keyframes_culled = 0;
  int bundle_adjustments = 0;
  int bundle_adjustments_aborted = 0;
};

class LocalMapper : public KeyFrameSink, public MappingControl {
 public:
  LocalMapper(Map* map, const LocalMapperOptions& options, bool threaded);
  ~LocalMapper() override;
  LocalMapper(const LocalMapper&) = delete;
  LocalMapper& operator=(const LocalMapper&) = delete;

  // Receives every keyframe after local mapping processed it (on the mapping thread, or the
  // caller's in synchronous mode); must not block. Set before Start().
  void SetDownstream(std::function<void(KeyFrame*)> downstream) { downstream_ = std::move(downstream); }
  void Start();  // launches the worker thread (threaded mode; no-op otherwise)

  bool AcceptsKeyFrames() const override;
  int QueuedKeyFrames() const override;
  void InterruptBundleAdjustment() override { abort_ba_ = true; }
  bool ReserveKeyFrame() override;
  // Without a prior reservation the keyframe counts as reserved now (even during a pause).
  // Throws Error after Close() or when local mapping failed.
  void InsertKeyFrame(KeyFrame* keyframe) override;

  void Pause() override;
  void Resume() override;

  // Synchronous mode: processes every queued keyframe now, on the caller's thread (which must not
  // hold the map update mutex); threaded mode: waits until they are processed. Throws Error if
  // local mapping failed.
  void ProcessQueued();
  // Stops accepting keyframes, processes (or with drop_pending only inserts) the queued ones and
  // joins the worker. Idempotent. Throws Error if processing failed.
  void Close(bool drop_pending = false);

  LocalMapperStats stats() const;

 private:
  void HandleKeyFrame(KeyFrame* keyframe);  // the worker's handler: process, then finish
  void ProcessKeyFrame(KeyFrame* keyframe);
  void FinishKeyFrame();  // one in-flight keyframe done
  bool MoreWaiting() const;

  Map* map_;
  LocalMapperOptions options_;
  const bool threaded_;
  std::atomic<bool> abort_ba_{false};
  std::atomic<bool> drop_pending_{false};
  std::function<void(KeyFrame*)> downstream_;
  // Pause state, under pause_mutex_: keyframes reserved or inserted and not finished, reserved
  // but not yet inserted, pause requests. in_flight_ mirrors in_flight for lock-free reads.
  mutable std::mutex pause_mutex_;
  std::condition_variable pause_cv_;
  int in_flight_locked_ = 0;
  int reserved_ = 0;
  int pause_requests_ = 0;
  std::atomic<int> in_flight_{0};
  std::vector<MapPoint*> recent_points_;  // worker-owned
  mutable std::mutex stats_mutex_;
  LocalMapperStats stats_;
  Worker<KeyFrame*> worker_;  // last: stopped before the state its handler uses
};

}  // namespace esdslam
