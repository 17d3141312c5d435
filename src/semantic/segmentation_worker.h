#pragma once
// The segmentation thread. Owns a Segmenter and runs it on submitted frames on its own thread (a
// Worker, common/worker.h, always threaded: the order of results does not depend on timing in
// every-frame mode, and real-time mode is about timing).
//
// Modes:
//   kEveryFrame  every submitted frame is segmented, in order. Submit blocks while `queue_capacity`
//                frames are waiting (back-pressure); tracking calls WaitFor(id) for each frame.
//   kNewestWins  real time: at most one frame waits; a newer submission replaces it, so when the
//                network becomes free it takes the newest frame. Submit never blocks. Tracking
//                calls Latest() for the newest finished result (never waits), or WaitFor(id),
//                which returns nullopt for frames that were replaced.
// Frame ids must increase with every Submit. Results are kept for the last `keep_results`
// processed frames; their cv::Mats are shared, treat them as read-only.
// If the segmenter throws, no later frame is segmented; WaitFor / Latest / the next Submit throw
// Error("segmentation failed: frame <id> (t=<timestamp>): <what>").
//
// Threads and locks: any thread may submit (submit_mutex_ serialises the id check and the push)
// and wait. mutex_ guards the results and statistics; the segmenter runs without it. The two are
// never held together except submit_mutex_ -> mutex_ (counting a submission) and
// submit_mutex_ -> the worker's queue mutex (the push); the worker's thread takes mutex_ only.

#include <condition_variable>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include <opencv2/core.hpp>

#include "common/worker.h"
#include "semantic/segmenter.h"

namespace esdslam {

enum class SegmentationMode { kEveryFrame, kNewestWins };

struct SegmentationWorkerOptions {
  SegmentationMode mode = SegmentationMode::kEveryFrame;
  int queue_capacity = 2;   // frames waiting in kEveryFrame mode
  int keep_results = 64;    // finished results kept for lookup by id

  void Check() const;
};

struct SegmentationFrame {
  std::int64_t id = 0;
  double timestamp = 0.0;  // seconds
  cv::Mat bgr;             // CV_8UC3; not modified by the worker
};

struct SegmentedFrame {
  std::int64_t id = 0;
  double timestamp = 0.0;
  SegmentationResult result;
  double latency_ms = 0.0;  // from Submit to result available (queueing + segmentation)
};

struct SegmentationWorkerStats {
  std::int64_t submitted = 0;
  std::int64_t processed = 0;
  std::int64_t replaced = 0;  // frames never segmented because a newer one replaced them (kNewestWins)
  double mean_segment_ms = 0.0;
  double mean_latency_ms = 0.0;
};

class SegmentationWorker {
 public:
  SegmentationWorker(std::unique_ptr<Segmenter> segmenter, SegmentationWorkerOptions options = {});
  ~SegmentationWorker();  // Stop()
  SegmentationWorker(const SegmentationWorker&) = delete;
  SegmentationWorker& operator=(const SegmentationWorker&) = delete;

  // Returns false after Stop(). Throws Error if ids do not increase or segmentation failed.
  bool Submit(SegmentationFrame frame);

  // Blocks until frame `id` is segmented. nullopt if it was replaced (kNewestWins), was never
  // submitted before Stop(), or has already dropped out of the kept results.
  std::optional<SegmentedFrame> WaitFor(std::int64_t id);
  // The most recent finished result, without waiting.
  std::optional<SegmentedFrame> Latest();

  // Stops accepting frames, finishes the frames already queued, joins the thread. Idempotent;
  // does not throw (a failure is reported by WaitFor, Latest and Submit).
  void Stop();

  SegmentationWorkerStats Stats() const;

 private:
  struct Job {
    SegmentationFrame frame;
    double submit_ms;  // steady clock, milliseconds
  };
  void Segment(Job& job);  // the worker's handler
  bool Enqueue(Job job);
  void Fail(const std::string& what);  // wakes the waiters
  void Publish(SegmentedFrame done);
  void ThrowIfFailed() const;  // requires mutex_ held

  std::unique_ptr<Segmenter> segmenter_;
  const SegmentationWorkerOptions options_;
  std::mutex submit_mutex_;  // serialises Submit (id order check + queue push)
  std::optional<std::int64_t> last_submitted_id_;
  bool stopped_ = false;     // Stop() ran (owner)

  mutable std::mutex mutex_;  // guards everything below
  std::condition_variable result_ready_;
  std::map<std::int64_t, SegmentedFrame> results_;
  std::optional<std::int64_t> last_processed_id_;
  bool in_progress_ = false;  // the thread is segmenting a frame
  bool finished_ = false;     // no result will come any more (stopped or failed)
  std::string failure_;    // segmenter error message, empty if none
  SegmentationWorkerStats stats_;

  Worker<Job> worker_;  // last: stopped before the state its handler uses
};

}  // namespace esdslam
