#include "dynamic/mask_ahead.h"

#include <utility>

#include <fmt/format.h>

#include "common/error.h"
#include "common/timer.h"

namespace esdslam {

MaskAhead::MaskAhead(std::unique_ptr<SemanticFrontEnd> front_end, WorkerMode mode)
    : front_end_(std::move(front_end)),
      // Two frames: the one being masked and the look-ahead one behind it.
      worker_("mask stage", mode, 2, [this](Job& job) { Make(job); }) {
  if (!front_end_) throw Error("MaskAhead: no semantic front end");
  worker_.Start();
}

MaskAhead::~MaskAhead() {
  try {
    Stop();
  } catch (const std::exception&) {  // logged by the worker when it happened
  }
}

void MaskAhead::Label(std::int64_t id, double timestamp, const cv::Mat& bgr) {
  if (id <= labelled_until_)
    throw Error(fmt::format("mask stage: frame {} labelled after frame {}", id, labelled_until_));
  if (worker_.threaded()) {
    std::lock_guard<std::mutex> lock(mutex_);
    ThrowIfFailed();
  }
  labelled_until_ = id;
  front_end_->Submit(id, timestamp, bgr);
}

void MaskAhead::Submit(std::int64_t id, double timestamp, const cv::Mat& bgr, const cv::Mat& depth_m) {
  if (id > labelled_until_) Label(id, timestamp, bgr);
  if (!worker_.threaded()) return;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ThrowIfFailed();
  }
  if (!worker_.Push({id, timestamp, bgr, depth_m})) throw Error("mask stage: frame submitted after Stop");
}

MaskAheadResult MaskAhead::MaskFor(std::int64_t id, const cv::Mat& bgr, const cv::Mat& depth_m) {
  MaskAheadResult out;
  if (!worker_.threaded()) {
    out.mask = front_end_->MaskFor(id, bgr, depth_m);
    return out;
  }
  Stopwatch wait;
  std::unique_lock<std::mutex> lock(mutex_);
  ready_.wait(lock, [&] { return !failure_.empty() || results_.count(id) > 0; });
  if (results_.count(id) == 0) ThrowIfFailed();  // a mask made before a later frame failed is still given
  out.wait_ms = wait.ElapsedMs();
  auto it = results_.find(id);
  out.mask = std::move(it->second);
  results_.erase(it);
  return out;
}

void MaskAhead::Make(Job& job) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (stopping_ || !failure_.empty()) return;
  }
  try {
    DynamicMaskResult mask = front_end_->MaskFor(job.id, job.bgr, job.depth_m);
    std::lock_guard<std::mutex> lock(mutex_);
    results_.emplace(job.id, std::move(mask));
  } catch (const std::exception& e) {
    std::lock_guard<std::mutex> lock(mutex_);
    failure_ = fmt::format("mask stage failed: frame {}: {}", job.id, e.what());
  }
  ready_.notify_all();
}

void MaskAhead::ThrowIfFailed() const {
  if (!failure_.empty()) throw Error(failure_);
}

void MaskAhead::Stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  worker_.Close();
  front_end_->Stop();
}

}  // namespace esdslam
