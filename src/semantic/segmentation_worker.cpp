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
      queue_(options.mode == SegmentationMode::kNewestWins ? 1 : static_cast<std::size_t>(options.queue_capacity)) {
  if (!segmenter_) throw Error("SegmentationWorker needs a segmenter");
  thread_ = std::thread([this] { Run(); });
}

SegmentationWorker::~SegmentationWorker() { Stop(); }

bool SegmentationWorker::Submit(SegmentationFrame frame) {
  if (frame.bgr.empty()) throw Error("SegmentationWorker::Submit: empty frame");
  std::lock_guard<std::mutex> submit_lock(submit_mutex_);
  if (last_submitted_id_ && frame.id <= *last_submitted_id_)
    throw Error(fmt::format("segmentation frame ids must increase ({} after {})", frame.id, *last_submitted_id_));
  last_submitted_id_ = frame.id;
  Job job{std::move(frame), NowMs()};
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ++stats_.submitted;  // counted before the push so that processed <= submitted at all times
  }
  const bool accepted = options_.mode == SegmentationMode::kNewestWins ? queue_.PushDropOldest(std::move(job))
                                                                       : queue_.Push(std::move(job));
  if (!accepted) {
    std::lock_guard<std::mutex> lock(mutex_);
    --stats_.submitted;
  }
  return accepted;
}

void SegmentationWorker::Run() {
  while (std::optional<Job> job = queue_.Pop()) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      in_progress_ = true;
    }
    SegmentedFrame done;
    done.id = job->frame.id;
    done.timestamp = job->frame.timestamp;
    try {
      done.result = segmenter_->Segment(job->frame.bgr, job->frame.timestamp);
    } catch (const std::exception& e) {
      spdlog::error("segmentation of frame {} failed: {}", done.id, e.what());
      std::lock_guard<std::mutex> lock(mutex_);
      failure_ = fmt::format("segmentation of frame {} (t={:.6f}) failed: {}", done.id, done.timestamp, e.what());
      break;
    }
    done.latency_ms = NowMs() - job->submit_ms;
    spdlog::debug("segmentation: frame {} segment {:.1f} ms, latency {:.1f} ms", done.id, done.result.segment_ms,
                  done.latency_ms);
    Publish(std::move(done));
  }
  queue_.Close();  // after a failure, refuse further frames
  std::lock_guard<std::mutex> lock(mutex_);
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
  queue_.Close();
  if (thread_.joinable()) {
    thread_.join();
    const SegmentationWorkerStats s = Stats();
    spdlog::info("segmentation thread ({}): {} frames segmented, {} replaced, mean {:.1f} ms per frame, "
                 "mean latency {:.1f} ms",
                 segmenter_->Name(), s.processed, s.replaced, s.mean_segment_ms, s.mean_latency_ms);
  }
}

SegmentationWorkerStats SegmentationWorker::Stats() const {
  const auto waiting = static_cast<std::int64_t>(queue_.Size());
  std::lock_guard<std::mutex> lock(mutex_);
  SegmentationWorkerStats s = stats_;
  if (failure_.empty())
    s.replaced = std::max<std::int64_t>(0, s.submitted - s.processed - waiting - (in_progress_ ? 1 : 0));
  return s;
}

}  // namespace esdslam
