// Frames decoded ahead on the loader thread (io/prefetching_source.h): same frames, same order,
// errors after the frames before them, early destruction.
#include <gtest/gtest.h>

#include <memory>
#include <vector>

#include "common/error.h"
#include "io/prefetching_source.h"

namespace esdslam {
namespace {

// Frames 0..n-1 (timestamp = index); throws InputError at frame `fail_at` (-1: never).
class CountingSource final : public FrameSource {
 public:
  CountingSource(int n, int fail_at = -1) : n_(n), fail_at_(fail_at) {}
  std::optional<RgbdFrame> Next() override {
    if (next_ == fail_at_) throw InputError("frames.txt", next_ + 1, "frame unreadable");
    if (next_ >= n_) return std::nullopt;
    RgbdFrame frame;
    frame.timestamp = next_++;
    frame.bgr = cv::Mat(4, 4, CV_8UC3, cv::Scalar::all(frame.timestamp));
    frame.depth_m = cv::Mat(4, 4, CV_32F, cv::Scalar(1.0f));
    return frame;
  }
  std::optional<std::size_t> frame_count() const override { return n_; }

 private:
  int n_, fail_at_;
  int next_ = 0;
};

TEST(PrefetchingFrameSourceTest, SameFramesInTheSameOrder) {
  PrefetchingFrameSource source(std::make_unique<CountingSource>(25), 3);
  EXPECT_EQ(source.frame_count(), 25u);
  for (int i = 0; i < 25; ++i) {
    const std::optional<RgbdFrame> frame = source.Next();
    ASSERT_TRUE(frame.has_value()) << i;
    EXPECT_EQ(frame->timestamp, i);
    EXPECT_EQ(frame->bgr.at<cv::Vec3b>(0, 0)[0], i);
  }
  EXPECT_FALSE(source.Next().has_value());
  EXPECT_FALSE(source.Next().has_value());
}

TEST(PrefetchingFrameSourceTest, AnErrorComesAfterTheFramesBeforeIt) {
  PrefetchingFrameSource source(std::make_unique<CountingSource>(20, 7));
  for (int i = 0; i < 7; ++i) ASSERT_EQ(source.Next()->timestamp, i);
  EXPECT_THROW(source.Next(), InputError);
  EXPECT_FALSE(source.Next().has_value());
}

TEST(PrefetchingFrameSourceTest, DestroyedBeforeTheEndWithoutWaitingForIt) {
  auto source = std::make_unique<PrefetchingFrameSource>(std::make_unique<CountingSource>(100000), 4);
  EXPECT_EQ(source->Next()->timestamp, 0);
  source.reset();  // the loader stops after the reads already queued
  SUCCEED();
}

}  // namespace
}  // namespace esdslam
