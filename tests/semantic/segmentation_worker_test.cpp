#include "semantic/segmentation_worker.h"

#include <condition_variable>
#include <mutex>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "common/error.h"

namespace esdslam {
namespace {

// Labels every pixel with the frame's pixel value (the test writes the frame id there). Can be
// held at the start of Segment() until Open(), and can fail on one timestamp.
class FakeSegmenter : public Segmenter {
 public:
  struct Shared {
    std::mutex mutex;
    std::condition_variable changed;
    bool open = true;
    std::vector<double> started;  // timestamps in call order
    double fail_at = -1.0;
  };
  explicit FakeSegmenter(std::shared_ptr<Shared> shared) : shared_(std::move(shared)) {}

  SegmentationResult Segment(const cv::Mat& bgr, double timestamp) override {
    std::unique_lock<std::mutex> lock(shared_->mutex);
    shared_->started.push_back(timestamp);
    shared_->changed.notify_all();
    shared_->changed.wait(lock, [&] { return shared_->open; });
    if (timestamp == shared_->fail_at) throw Error("fake failure");
    SegmentationResult r;
    cv::extractChannel(bgr, r.labels, 0);
    r.segment_ms = 1.0;
    return r;
  }
  std::string Name() const override { return "fake"; }

 private:
  std::shared_ptr<Shared> shared_;
};

SegmentationFrame MakeFrame(std::int64_t id) {
  return {id, 100.0 + static_cast<double>(id), cv::Mat(3, 4, CV_8UC3, cv::Scalar::all(static_cast<double>(id)))};
}

void WaitStarted(FakeSegmenter::Shared& shared, std::size_t count) {
  std::unique_lock<std::mutex> lock(shared.mutex);
  shared.changed.wait(lock, [&] { return shared.started.size() >= count; });
}

void Open(FakeSegmenter::Shared& shared) {
  std::lock_guard<std::mutex> lock(shared.mutex);
  shared.open = true;
  shared.changed.notify_all();
}

TEST(SegmentationWorker, EveryFrameSegmentsAllFramesInOrderWithTheirOwnResults) {
  auto shared = std::make_shared<FakeSegmenter::Shared>();
  SegmentationWorker worker(std::make_unique<FakeSegmenter>(shared));
  std::thread producer([&] {
    for (int id = 1; id <= 30; ++id) ASSERT_TRUE(worker.Submit(MakeFrame(id)));
  });
  for (int id = 1; id <= 30; ++id) {
    const auto done = worker.WaitFor(id);
    ASSERT_TRUE(done.has_value()) << id;
    EXPECT_EQ(done->id, id);
    EXPECT_DOUBLE_EQ(done->timestamp, 100.0 + id);
    EXPECT_EQ(done->result.labels.at<uchar>(2, 3), id);
    EXPECT_GE(done->latency_ms, 0.0);
  }
  producer.join();
  worker.Stop();
  EXPECT_EQ(shared->started.size(), 30u);
  for (std::size_t i = 0; i < shared->started.size(); ++i) EXPECT_DOUBLE_EQ(shared->started[i], 101.0 + i);
  EXPECT_EQ(worker.Stats().processed, 30);
  EXPECT_EQ(worker.Stats().replaced, 0);
}

TEST(SegmentationWorker, StopFinishesQueuedFramesThenRefusesNewOnes) {
  auto shared = std::make_shared<FakeSegmenter::Shared>();
  shared->open = false;
  SegmentationWorker worker(std::make_unique<FakeSegmenter>(shared));
  ASSERT_TRUE(worker.Submit(MakeFrame(1)));
  WaitStarted(*shared, 1);
  ASSERT_TRUE(worker.Submit(MakeFrame(2)));  // both fit in the queue (capacity 2)
  ASSERT_TRUE(worker.Submit(MakeFrame(3)));
  Open(*shared);
  worker.Stop();
  EXPECT_EQ(worker.Stats().processed, 3);
  EXPECT_FALSE(worker.Submit(MakeFrame(4)));
  EXPECT_FALSE(worker.WaitFor(4).has_value());  // never submitted: returns, does not hang
  ASSERT_TRUE(worker.WaitFor(3).has_value());
  EXPECT_EQ(worker.Latest()->id, 3);
}

TEST(SegmentationWorker, NewestWinsTakesTheNewestFrameWhenTheNetworkIsFree) {
  auto shared = std::make_shared<FakeSegmenter::Shared>();
  shared->open = false;
  SegmentationWorkerOptions options;
  options.mode = SegmentationMode::kNewestWins;
  SegmentationWorker worker(std::make_unique<FakeSegmenter>(shared), options);
  ASSERT_TRUE(worker.Submit(MakeFrame(1)));
  WaitStarted(*shared, 1);
  for (int id = 2; id <= 5; ++id) ASSERT_TRUE(worker.Submit(MakeFrame(id)));  // never blocks
  EXPECT_FALSE(worker.Latest().has_value());  // nothing finished yet, and Latest() does not wait
  Open(*shared);
  const auto newest = worker.WaitFor(5);
  ASSERT_TRUE(newest.has_value());
  EXPECT_EQ(newest->result.labels.at<uchar>(0, 0), 5);
  EXPECT_FALSE(worker.WaitFor(3).has_value());  // replaced by 4, then 5
  ASSERT_TRUE(worker.WaitFor(1).has_value());
  EXPECT_EQ(worker.Latest()->id, 5);
  worker.Stop();
  ASSERT_EQ(shared->started.size(), 2u);
  EXPECT_DOUBLE_EQ(shared->started[1], 105.0);
  EXPECT_EQ(worker.Stats().processed, 2);
  EXPECT_EQ(worker.Stats().replaced, 3);
}

TEST(SegmentationWorker, SegmenterErrorReachesTheWaitingThread) {
  auto shared = std::make_shared<FakeSegmenter::Shared>();
  shared->fail_at = 103.0;
  SegmentationWorker worker(std::make_unique<FakeSegmenter>(shared));
  for (int id = 1; id <= 3; ++id) ASSERT_TRUE(worker.Submit(MakeFrame(id)));
  EXPECT_TRUE(worker.WaitFor(2).has_value());
  EXPECT_THROW(worker.WaitFor(3), Error);
  EXPECT_THROW(worker.Latest(), Error);
}

TEST(SegmentationWorker, SubmitAfterAFailureThrowsIt) {
  auto shared = std::make_shared<FakeSegmenter::Shared>();
  shared->fail_at = 101.0;
  SegmentationWorker worker(std::make_unique<FakeSegmenter>(shared));
  ASSERT_TRUE(worker.Submit(MakeFrame(1)));
  EXPECT_THROW(worker.WaitFor(1), Error);
  try {
    worker.Submit(MakeFrame(2));
    ADD_FAILURE() << "Submit did not throw";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "segmentation failed: frame 1 (t=101.000000): fake failure");
  }
  worker.Stop();  // does not throw
  EXPECT_EQ(shared->started.size(), 1u);
}

TEST(SegmentationWorker, IdsMustIncrease) {
  auto shared = std::make_shared<FakeSegmenter::Shared>();
  SegmentationWorker worker(std::make_unique<FakeSegmenter>(shared));
  ASSERT_TRUE(worker.Submit(MakeFrame(7)));
  EXPECT_THROW(worker.Submit(MakeFrame(7)), Error);
  EXPECT_THROW(worker.Submit(MakeFrame(3)), Error);
}

TEST(SegmentationWorker, DestructorWithQueuedFramesJoins) {
  auto shared = std::make_shared<FakeSegmenter::Shared>();
  {
    SegmentationWorker worker(std::make_unique<FakeSegmenter>(shared));
    for (int id = 1; id <= 3; ++id) worker.Submit(MakeFrame(id));
  }
  EXPECT_EQ(shared->started.size(), 3u);
}

}  // namespace
}  // namespace esdslam
