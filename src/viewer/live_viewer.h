#pragma once
// The live viewer of a run (`esdslam run --viewer`): the run loop's frame callback hands each
// frame's report to Offer() on the tracking thread, which only copies it (image headers and
// shared pointers, no pixels) into a bounded queue; the viewer's own thread (the project's
// Worker, "viewer") encodes it (frame_view.h), reads the map now and then (map_view.h) and
// publishes both to the event hub, from which the HTTP server streams them (viewer_server.h).
//
// Decimation and drops, so that tracking never waits for the viewer or a browser:
//   - Offer() passes on at most one frame per ViewerOptions::frame_interval_ms (the others are
//     counted as skipped);
//   - the queue holds queue_capacity frames; a frame offered while it is full replaces the
//     oldest (newest wins; counted as dropped); Offer never blocks;
//   - the hub keeps only the newest event of each name (event_hub.h) for slow browsers;
//   - the map is read at most every map_interval_ms, thinned to the options' maxima.
//
// Threads and shared data: Offer and Finish are for the tracking thread (the owner); the
// viewer thread reads the SLAM system (Trajectory, KeyFrameTrajectory, map points: their own
// locks, so it may wait for a tracking step, never the other way round) and the dense mapper's
// CurrentCloud; it owns the counters of what it encoded. The queue's and hub's mutexes and
// culled_mutex_ (the culled map points handed over from every frame) are leaves.
// The system and the dense mapper must outlive the viewer (Close joins the thread).

#include <atomic>
#include <memory>
#include <mutex>
#include <vector>
#include <optional>
#include <string>

#include "common/timer.h"
#include "common/worker.h"
#include "dense/dense_mapper.h"
#include "system/frame_report.h"
#include "system/slam_system.h"
#include "viewer/event_hub.h"
#include "viewer/frame_view.h"
#include "viewer/map_view.h"
#include "viewer/viewer_options.h"
#include "viewer/viewer_server.h"

namespace esdslam {

struct ViewerStats {
  long offered = 0;  // frames given to Offer
  long skipped = 0;  // not passed on: within frame_interval_ms of the previous one
  long dropped = 0;  // passed on, then replaced in the full queue by a newer one
  long encoded = 0;  // frame events published
  long maps = 0;     // map events published
  double frame_cpu_ms = 0;  // CPU time of the viewer thread encoding frame events
  double map_cpu_ms = 0;    // CPU time of the viewer thread reading and encoding the map
};

class LiveViewer {
 public:
  // Starts the server (throws Error as ViewerServer) and the viewer thread. dense may be null;
  // system may be null (no map, counts 0: the tests of the frame path).
  // serve = false: no HTTP server (the benchmark's encode-only mode and the tests).
  LiveViewer(const ViewerOptions& options, SlamSystem* system, const DenseMapper* dense, bool serve = true);
  ~LiveViewer();
  LiveViewer(const LiveViewer&) = delete;
  LiveViewer& operator=(const LiveViewer&) = delete;

  // Tracking thread, after each frame: copies the report's headers, never blocks. When the
  // viewer thread has failed it logs that once and does nothing more (the run goes on).
  void Offer(const FrameReport& report);
  // After the run (final poses written): encodes the last frame and the final map, waits until
  // they are published. The server keeps serving them until Close.
  void Finish();
  // Stops the viewer thread and the server. Idempotent.
  void Close();

  std::string url() const { return server_ ? server_->url() : std::string(); }
  EventHub& hub() { return hub_; }
  ViewerStats stats() const;

 private:
  struct Job {
    FrameReport report;
    long dropped_total = 0;   // frames the source dropped up to this one
    double run_ms = 0;        // run time when it was offered
    long viewer_dropped = 0;  // skipped + dropped so far
    bool final = false;       // the end of the run: the final map as well
  };
  void Handle(Job& job);
  void PublishMap(bool finished);
  // The dense cloud, rebuilt when due (dense_interval_ms, new dense keyframes, or the end).
  const PointCloud& DenseCloud(bool finished);

  const ViewerOptions options_;
  SlamSystem* system_;
  const DenseMapper* dense_;
  EventHub hub_;
  std::unique_ptr<ViewerServer> server_;
  // Tracking thread only.
  Stopwatch run_clock_;
  std::optional<FrameReport> last_report_;
  double last_offer_ms_ = -1e18;
  long dropped_total_ = 0;
  bool failed_ = false;  // the viewer thread failed: Offer and Finish do nothing
  std::atomic<long> offered_{0}, skipped_{0}, dropped_{0};
  // Map points culled as moved, of every frame (skipped and dropped ones too): appended by Offer,
  // taken by the viewer thread. culled_mutex_ is a leaf. At most max_dynamic_points wait.
  std::mutex culled_mutex_;
  std::vector<Eigen::Vector3f> culled_pending_;
  // Viewer thread only (read by stats() after Finish/Close, or as atomics).
  DynamicPointTrail trail_;
  DynamicPointTrail culled_trail_;
  Stopwatch map_clock_;
  bool map_published_ = false;
  Stopwatch dense_clock_;
  long dense_keyframes_ = -1;  // dense keyframes in dense_cloud_; -1 = not built yet
  PointCloud dense_cloud_;     // decimated
  std::atomic<long> encoded_{0}, maps_{0};
  std::atomic<double> frame_cpu_ms_{0}, map_cpu_ms_{0};
  std::unique_ptr<Worker<Job>> worker_;  // last: closed (joined) before the rest goes
};

}  // namespace esdslam
