#include "semantic/segmentation_worker.h"

#include <algorithm>
#include <chrono>

#include <spdlog/spdlog.h>

#include "common/error.h"

namespace esdslam {
namespace {

double NowMs() {
  using namespace std::chrono;
  return duration<double, std::milli>(steady_clock::now().time_since_epoch()).count();
}

}  // namespace

void SegmentationWorkerOptions::Check() const {
  if (queue_capacity < 1) throw Error("segmentation queue capacity must be >= 1");
  if (keep_results < 1) throw Error("segmentation worker must keep at least 1 result");
}

SegmentationWorker::SegmentationWorker(std::unique_ptr<Segmenter> segmenter, SegmentationWorkerOptions options)
    : segmenter_(std::move(segmenter)),
      options_((options.Check(), options)),
      worker_("segmentation", WorkerMode::kThread,
              options.mode == SegmentationMode::kNewestWins ? 1 : static_cast<std::size_t>(options.queue_capacity),
              [this](Job& job) { Segment(job); }) {
  if (!segmenter_) throw Error("SegmentationWorker needs a segmenter");
  worker_.Start();
}

SegmentationWorker::~SegmentationWorker() { Stop(); }

bool SegmentationWorker::Submit(SegmentationFrame frame) {
  if (frame.bgr.empty()) throw Error("SegmentationWorker::Submit: empty frame");
  std::lock_guard<std::mutex> submit_lock(submit_mutex_);
  if (last_submitted_id_ && frame.id <= *last_submitted_id_)
    throw Error(fmt::format("segmentation frame ids must increase ({} after {})", frame.id, *last_submitted_id_));
  last_submitted_id_ = frame.id;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ThrowIfFailed();     // as soon as WaitFor would (the worker may not have recorded it yet)
    ++stats_.submitted;  // counted before the push so that processed <= submitted at all times
  }
  const auto uncount = [this] {
    std::lock_guard<std::mutex> lock(mutex_);
    --stats_.submitted;
  };
  bool accepted = false;
  try {
    accepted = Enqueue({std::move(frame), NowMs()});
  } catch (const Error&) {  // segmentation failed
    uncount();
    throw;
  }
  if (!accepted) uncount();
  return accepted;
}

bool SegmentationWorker::Enqueue(Job job) {
  if (options_.mode == SegmentationMode::kNewestWins)
    return worker_.PushDropOldest(std::move(job)) != DropOldestPush::kClosed;
  return worker_.Push(std::move(job));
}

void SegmentationWorker::Segment(Job& job) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!failure_.empty()) return;  // after a failure no frame is segmented
    in_progress_ = true;
  }
  SegmentedFrame done;
  done.id = job.frame.id;
  done.timestamp = job.frame.timestamp;
  try {
    done.result = segmenter_->Segment(job.frame.bgr, job.frame.timestamp);
  } catch (const std::exception& e) {
    const std::string what = fmt::format("frame {} (t={:.6f}): {}", done.id, done.timestamp, e.what());
    Fail(what);
    throw Error(what);  // the worker keeps it ("segmentation failed: ...") for Submit
  }
  done.latency_ms = NowMs() - job.submit_ms;
  spdlog::debug("segmentation: frame {} segment {:.1f} ms, latency {:.1f} ms", done.id, done.result.segment_ms,
                done.latency_ms);
  Publish(std::move(done));
}

void SegmentationWorker::Fail(const std::string& what) {
  std::lock_guard<std::mutex> lock(mutex_);
  failure_ = fmt::format("{} failed: {}", worker_.name(), what);  // as the worker words it
  finished_ = true;
  result_ready_.notify_all();
}

void SegmentationWorker::Publish(SegmentedFrame done) {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto n = static_cast<double>(stats_.processed);
  stats_.mean_segment_ms = (stats_.mean_segment_ms * n + done.result.segment_ms) / (n + 1);
  stats_.mean_latency_ms = (stats_.mean_latency_ms * n + done.latency_ms) / (n + 1);
  ++stats_.processed;
  in_progress_ = false;
  last_processed_id_ = done.id;
  results_[done.id] = std::move(done);
  while (results_.size() > static_cast<std::size_t>(options_.keep_results)) results_.erase(results_.begin());
  result_ready_.notify_all();
}

void SegmentationWorker::ThrowIfFailed() const {
  if (!failure_.empty()) throw Error(failure_);
}

std::optional<SegmentedFrame> SegmentationWorker::WaitFor(std::int64_t id) {
  std::unique_lock<std::mutex> lock(mutex_);
  // Frames are processed in id order, so a later processed id means `id` will never come.
  result_ready_.wait(lock, [&] { return finished_ || (last_processed_id_ && *last_processed_id_ >= id); });
  const auto it = results_.find(id);
  if (it != results_.end()) return it->second;
  ThrowIfFailed();
  return std::nullopt;
}

std::optional<SegmentedFrame> SegmentationWorker::Latest() {
  std::lock_guard<std::mutex> lock(mutex_);
  ThrowIfFailed();
  if (!last_processed_id_) return std::nullopt;
  const auto it = results_.find(*last_processed_id_);
  if (it == results_.end()) return std::nullopt;
  return it->second;
}

void SegmentationWorker::Stop() {
  if (stopped_) return;
  stopped_ = true;
  try {
    worker_.Close();
  } catch (const Error&) {  // reported by WaitFor, Latest and Submit
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    finished_ = true;
    result_ready_.notify_all();
  }
  const SegmentationWorkerStats s = Stats();
  spdlog::info("segmentation thread ({}): {} frames segmented, {} replaced, mean {:.1f} ms per frame, "
               "mean latency {:.1f} ms",
               segmenter_->Name(), s.processed, s.replaced, s.mean_segment_ms, s.mean_latency_ms);
}

SegmentationWorkerStats SegmentationWorker::Stats() const {
  const auto waiting = static_cast<std::int64_t>(worker_.Queued());
  std::lock_guard<std::mutex> lock(mutex_);
  SegmentationWorkerStats s = stats_;
  if (failure_.empty())
    s.replaced = std::max<std::int64_t>(0, s.submitted - s.processed - waiting - (in_progress_ ? 1 : 0));
  return s;
}

}  // namespace esdslam
