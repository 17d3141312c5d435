#include "common/worker.h"

#include <condition_variable>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "common/error.h"

namespace esdslam {
namespace {

// What a handler saw, and a gate that can hold it at the start of a job until Open(). Waits are
// on a condition variable only.
class Recorder {
 public:
  explicit Recorder(bool open = true) : open_(open) {}

  void Handle(int job) {
    std::unique_lock<std::mutex> lock(mutex_);
    started_.push_back(job);
    changed_.notify_all();
    changed_.wait(lock, [&] { return open_; });
    if (job < 0) throw std::runtime_error("bad job " + std::to_string(job));
    handled_.push_back(job);
  }
  void Open() {
    std::lock_guard<std::mutex> lock(mutex_);
    open_ = true;
    changed_.notify_all();
  }
  void WaitStarted(std::size_t count) {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(lock, [&] { return started_.size() >= count; });
  }
  std::vector<int> handled() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return handled_;
  }
  std::vector<int> started() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return started_;
  }

 private:
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  bool open_;
  std::vector<int> started_, handled_;
};

Worker<int>::Handler HandlerOf(Recorder& recorder) {
  return [&recorder](int job) { recorder.Handle(job); };
}

std::string ErrorOf(const std::function<void()>& call) {
  try {
    call();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

std::vector<int> HandledWith(WorkerMode mode, const std::vector<int>& jobs) {
  Recorder recorder;
  Worker<int> worker("test", mode, 3, HandlerOf(recorder));
  worker.Start();
  for (std::size_t i = 0; i < jobs.size(); ++i) {
    EXPECT_TRUE(worker.Push(jobs[i]));
    if (i % 7 == 6) worker.Drain();  // as the system drains after each frame
  }
  worker.Close();
  return recorder.handled();
}

TEST(Worker, InlineAndThreadedHandleTheSameJobsInTheSameOrder) {
  std::vector<int> jobs;
  for (int i = 0; i < 100; ++i) jobs.push_back((i * 37) % 101);
  EXPECT_EQ(HandledWith(WorkerMode::kInline, jobs), jobs);
  EXPECT_EQ(HandledWith(WorkerMode::kThread, jobs), jobs);
}

TEST(Worker, InlineJobsRunOnlyWhenTheOwnerDrains) {
  Recorder recorder;
  Worker<int> worker("test", WorkerMode::kInline, 2, HandlerOf(recorder));
  worker.Start();  // no thread in inline mode
  worker.Push(1);
  worker.Push(2);
  EXPECT_TRUE(recorder.handled().empty());
  EXPECT_EQ(worker.Queued(), 2u);
  worker.Push(3);  // full: the oldest is handled first, here
  EXPECT_EQ(recorder.handled(), (std::vector<int>{1}));
  worker.Drain();
  EXPECT_EQ(recorder.handled(), (std::vector<int>{1, 2, 3}));
  EXPECT_EQ(worker.Queued(), 0u);
}

TEST(Worker, DrainWaitsForTheThreadToHandleEveryJob) {
  Recorder recorder;
  Worker<int> worker("test", WorkerMode::kThread, 4, HandlerOf(recorder));
  worker.Start();
  for (int i = 0; i < 50; ++i) worker.Push(i);
  worker.Drain();
  EXPECT_EQ(recorder.handled().size(), 50u);
  worker.Close();
}

void ExpectFirstErrorOnNextPushAndOnClose(WorkerMode mode) {
  Recorder recorder;
  Worker<int> worker("stage", mode, 8, HandlerOf(recorder));
  worker.Start();
  for (const int job : {1, -3, 4, -5, 6}) worker.Push(job);
  worker.Drain();  // does not throw
  EXPECT_EQ(recorder.handled(), (std::vector<int>{1, 4, 6}));  // handling goes on after an error
  EXPECT_TRUE(worker.failed());
  EXPECT_EQ(ErrorOf([&] { worker.Push(7); }), "stage failed: bad job -3");
  EXPECT_EQ(ErrorOf([&] { worker.PushDropOldest(8); }), "stage failed: bad job -3");
  EXPECT_EQ(ErrorOf([&] { worker.ThrowIfFailed(); }), "stage failed: bad job -3");
  EXPECT_EQ(ErrorOf([&] { worker.Close(); }), "stage failed: bad job -3");
  EXPECT_EQ(recorder.handled(), (std::vector<int>{1, 4, 6}));  // 7 and 8 were refused
  EXPECT_EQ(ErrorOf([&] { worker.Close(); }), "");  // idempotent
}

TEST(Worker, FirstErrorIsRethrownOnTheNextPushAndOnCloseInline) {
  ExpectFirstErrorOnNextPushAndOnClose(WorkerMode::kInline);
}

TEST(Worker, FirstErrorIsRethrownOnTheNextPushAndOnCloseThreaded) {
  ExpectFirstErrorOnNextPushAndOnClose(WorkerMode::kThread);
}

TEST(Worker, CloseHandlesTheQueuedJobsThenJoins) {
  Recorder recorder(false);
  Worker<int> worker("test", WorkerMode::kThread, 2, HandlerOf(recorder));
  worker.Start();
  worker.Push(1);
  recorder.WaitStarted(1);  // 1 is held in the handler
  worker.Push(2);
  worker.Push(3);  // the queue is full now
  std::thread closer([&] { worker.Close(); });
  // Blocks on the full queue until the closer closes it: then refused.
  EXPECT_FALSE(worker.Push(4));
  recorder.Open();
  closer.join();
  EXPECT_EQ(recorder.handled(), (std::vector<int>{1, 2, 3}));
  EXPECT_FALSE(worker.Push(5));
}

TEST(Worker, CloseWithoutStartHandlesTheQueueOnTheCallersThread) {
  Recorder recorder;
  Worker<int> worker("test", WorkerMode::kThread, 4, HandlerOf(recorder));
  worker.Push(1);
  worker.Push(2);
  worker.Close();
  EXPECT_EQ(recorder.handled(), (std::vector<int>{1, 2}));
}

TEST(Worker, DropOldestNeverBlocksAndKeepsTheNewest) {
  Recorder recorder(false);
  Worker<int> worker("test", WorkerMode::kThread, 1, HandlerOf(recorder));
  worker.Start();
  EXPECT_EQ(worker.PushDropOldest(1), DropOldestPush::kQueued);
  recorder.WaitStarted(1);
  EXPECT_EQ(worker.PushDropOldest(2), DropOldestPush::kQueued);
  EXPECT_EQ(worker.PushDropOldest(3), DropOldestPush::kQueuedDroppedOldest);
  EXPECT_EQ(worker.PushDropOldest(4), DropOldestPush::kQueuedDroppedOldest);
  recorder.Open();
  worker.Drain();  // the dropped jobs do not count as pending
  EXPECT_EQ(recorder.handled(), (std::vector<int>{1, 4}));
  worker.Close();
  EXPECT_EQ(worker.PushDropOldest(5), DropOldestPush::kClosed);
}

TEST(Worker, DropOldestInlineKeepsTheNewestUpToCapacity) {
  Recorder recorder;
  Worker<int> worker("test", WorkerMode::kInline, 2, HandlerOf(recorder));
  for (int job = 1; job <= 4; ++job) worker.PushDropOldest(job);
  worker.Drain();
  EXPECT_EQ(recorder.handled(), (std::vector<int>{3, 4}));
}

}  // namespace
}  // namespace esdslam
