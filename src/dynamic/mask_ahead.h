#pragma once
// Each frame's dynamic mask made ahead of tracking, on a thread of its own (issue 12). The run
// loop submits frame i+1 before it tracks frame i; with a thread, the mask of i+1 (the labels
// carried along the optical flow, region growing, dilation: SemanticFrontEnd::MaskFor) is made
// while frame i is extracted and tracked, so it leaves the tracking thread's critical path.
//
// Two steps per frame: Label(id) hands the frame to the network's schedule at once, on the
// caller's thread (front_end.Submit; the run loop does it Semantic.lookAhead frames before the
// frame is tracked), Submit(id) queues its mask (one frame ahead of tracking).
// WorkerMode::kThread: the thread calls front_end.MaskFor(id) for every submitted frame, in
//   order; the front end's Submit runs on the caller's thread (the front end allows those two
//   threads). MaskFor(id) on the caller's side waits for frame id's mask (MaskAheadResult::wait_ms
//   says how long).
// WorkerMode::kInline (--single-thread): no thread; Label calls the front end's Submit when the
//   frame is submitted ahead and MaskFor calls its MaskFor when the frame is tracked, both on the
//   caller's thread; Submit only records the frame.
//
// Errors: a failure of the front end (e.g. the network's) is kept and thrown by the next MaskFor
// or Submit, as Error("mask stage failed: ...").
//
// Threads and locks: mutex_ guards results_ and failure_ (a leaf); the worker's queue has its own.

#include <condition_variable>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include <opencv2/core.hpp>

#include "common/worker.h"
#include "dynamic/semantic_front_end.h"

namespace esdslam {

struct MaskAheadResult {
  DynamicMaskResult mask;
  double wait_ms = 0;  // time MaskFor blocked on the mask thread (0 inline)
};

class MaskAhead {
 public:
  MaskAhead(std::unique_ptr<SemanticFrontEnd> front_end, WorkerMode mode);
  ~MaskAhead();
  MaskAhead(const MaskAhead&) = delete;
  MaskAhead& operator=(const MaskAhead&) = delete;

  // Frame `id` (ids increase) to the network's schedule; bgr shared, never written afterwards.
  void Label(std::int64_t id, double timestamp, const cv::Mat& bgr);
  // Frame `id`'s mask queued (ids increase; Label(id) first if not done yet), images shared.
  void Submit(std::int64_t id, double timestamp, const cv::Mat& bgr, const cv::Mat& depth_m);
  // The mask of submitted frame `id` (asked in id order, each once). Throws Error.
  MaskAheadResult MaskFor(std::int64_t id, const cv::Mat& bgr, const cv::Mat& depth_m);
  // Stops the thread (frames submitted and not asked for are not masked) and the network.
  void Stop();

  const SemanticFrontEnd& front_end() const { return *front_end_; }

 private:
  struct Job {
    std::int64_t id;
    double timestamp;
    cv::Mat bgr, depth_m;
  };
  void Make(Job& job);
  void ThrowIfFailed() const;  // mutex_ held

  std::unique_ptr<SemanticFrontEnd> front_end_;
  mutable std::mutex mutex_;
  std::condition_variable ready_;
  std::map<std::int64_t, DynamicMaskResult> results_;  // made, not asked for yet
  std::string failure_;                                // the first failure; empty if none
  std::int64_t labelled_until_ = -1;                   // caller's thread: last id given to Label
  bool stopping_ = false;                              // Stop: the queued frames are skipped
  Worker<Job> worker_;                                 // last: its thread goes first
};

}  // namespace esdslam
