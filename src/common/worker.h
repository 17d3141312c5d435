#pragma once
// The one worker type for every stage thread (local mapping, loop closing, global BA, dense
// mapping, segmentation). Jobs wait in a BoundedQueue and are handled one at a time, in the order
// they were queued, by the owner's handler:
//   WorkerMode::kThread  on the worker's own std::thread, launched by Start(); it waits on the
//                        queue's condition variables (no polling). Push blocks while `capacity`
//                        jobs wait (back-pressure).
//   WorkerMode::kInline  on the owner's thread when it calls Drain() or Close(): the same jobs in
//                        the same order, so a run repeats exactly (--single-thread). Push never
//                        blocks: when `capacity` jobs wait it first handles the oldest, here.
// A kThread worker that was never started behaves like an inline one.
//
// Errors: the first exception a handler throws is kept (every one is logged) and handling goes on
// with the next job, so every accepted job is handled exactly once. The owner gets it as
// Error("<name> failed: <what>") from the next Push / PushDropOldest, from Close() and from
// ThrowIfFailed(). Drain() does not throw.
//
// Close(): refuses new jobs (Push returns false), handles every queued job, joins the thread.
//
// Threads and locks: the queue's mutex and state_mutex_ (pending count, error) are leaves: never
// held together, never held while a handler runs. Start and Close belong to the owner; Push,
// PushDropOldest, Drain, Queued and ThrowIfFailed may be called from any thread but the worker's
// own (a handler must not push to or drain its own worker). Everything a handler wrote is visible
// to the owner after Drain() or Close() returns.

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <exception>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <utility>

#include <spdlog/spdlog.h>

#include "common/bounded_queue.h"
#include "common/error.h"
#include "common/thread_name.h"

namespace esdslam {

enum class WorkerMode { kThread, kInline };

inline WorkerMode ThreadedOrInline(bool threaded) { return threaded ? WorkerMode::kThread : WorkerMode::kInline; }

template <typename Job>
class Worker {
 public:
  using Handler = std::function<void(Job&)>;

  // `name` appears in the log and in the rethrown error ("local mapping"). capacity >= 1.
  Worker(std::string name, WorkerMode mode, std::size_t capacity, Handler handler)
      : name_(std::move(name)), mode_(mode), capacity_(capacity == 0 ? 1 : capacity), queue_(capacity_),
        handler_(std::move(handler)) {}
  // Close(); an error is not thrown here (it was logged when it happened).
  ~Worker() {
    try {
      Close();
    } catch (const std::exception&) {
    }
  }
  Worker(const Worker&) = delete;
  Worker& operator=(const Worker&) = delete;

  // kThread: launches the thread (once; not after Close). kInline: nothing.
  void Start() {
    if (mode_ != WorkerMode::kThread || started_ || closed_) return;
    started_ = true;
    thread_ = std::thread([this] {
      NameThisThread(name_);
      while (std::optional<Job> job = queue_.Pop()) Handle(*job);
    });
  }

  // Queues `job`. Returns false once closed. Throws the first error.
  bool Push(Job job) {
    Accept();
    if (RunsHere())
      while (queue_.Size() >= capacity_ && RunOne()) {
      }
    if (queue_.Push(std::move(job))) return true;
    Release();
    return false;
  }

  // Never blocks: when `capacity` jobs wait, the oldest is dropped (never handled). Throws the
  // first error.
  DropOldestPush PushDropOldest(Job job) {
    Accept();
    const DropOldestPush result = queue_.PushDropOldest(std::move(job));
    if (result != DropOldestPush::kQueued) Release();  // closed: this job; dropped: the oldest
    return result;
  }

  // Returns once every job accepted so far is handled: kInline handles them here, kThread waits
  // for its thread.
  void Drain() {
    if (RunsHere()) {
      while (RunOne()) {
      }
      return;
    }
    std::unique_lock<std::mutex> lock(state_mutex_);
    idle_.wait(lock, [&] { return pending_ == 0; });
  }

  // Refuses new jobs, handles the queued ones, joins. Idempotent; the call that closes throws the
  // first error.
  void Close() {
    if (closed_) return;
    closed_ = true;
    queue_.Close();
    if (thread_.joinable()) thread_.join();
    while (RunOne()) {  // inline, or never started
    }
    ThrowIfFailed();
  }

  void ThrowIfFailed() const {
    std::lock_guard<std::mutex> lock(state_mutex_);
    if (!error_.empty()) throw Error(error_);
  }
  bool failed() const {
    std::lock_guard<std::mutex> lock(state_mutex_);
    return !error_.empty();
  }
  // Jobs waiting, not counting the one being handled.
  std::size_t Queued() const { return queue_.Size(); }
  bool threaded() const { return mode_ == WorkerMode::kThread; }
  const std::string& name() const { return name_; }

 private:
  bool RunsHere() const { return mode_ == WorkerMode::kInline || !started_; }

  // One more job accepted and not handled yet; refused after an error.
  void Accept() {
    std::lock_guard<std::mutex> lock(state_mutex_);
    if (!error_.empty()) throw Error(error_);
    ++pending_;
  }
  void Release() {
    std::lock_guard<std::mutex> lock(state_mutex_);
    if (--pending_ == 0) idle_.notify_all();
  }

  bool RunOne() {
    std::optional<Job> job = queue_.TryPop();
    if (!job) return false;
    Handle(*job);
    return true;
  }

  void Handle(Job& job) {
    try {
      handler_(job);
    } catch (const std::exception& e) {
      Fail(e.what());
    } catch (...) {
      Fail("unknown exception");
    }
    Release();
  }

  void Fail(const char* what) {
    const std::string message = fmt::format("{} failed: {}", name_, what);
    spdlog::error("{}", message);
    std::lock_guard<std::mutex> lock(state_mutex_);
    if (error_.empty()) error_ = message;
  }

  const std::string name_;
  const WorkerMode mode_;
  const std::size_t capacity_;
  BoundedQueue<Job> queue_;
  const Handler handler_;
  std::atomic<bool> started_{false};
  bool closed_ = false;  // owner only
  mutable std::mutex state_mutex_;
  std::condition_variable idle_;  // pending_ reached 0
  long pending_ = 0;              // accepted (queued or being handled), not yet handled
  std::string error_;             // the first failure, empty if none
  std::thread thread_;            // last: joined (by Close) before the rest goes
};

}  // namespace esdslam
