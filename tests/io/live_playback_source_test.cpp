// Sensor-clock playback on a manual clock: frames arrive at their timestamps, a frame nobody
// took before the next one arrived is dropped and counted, the last frame always arrives, an
// error of the wrapped source comes after the frames before it, and stopping mid-run joins.
// The test owns the clock: between AdvanceTo and Next it waits until the playback thread sleeps
// for a later frame (WaitForSleeper), so every run is the same.
#include <future>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "common/error.h"
#include "io/live_playback_source.h"
#include "io/playback_clock.h"

namespace esdslam {
namespace {

// Frames with the given times (1x1 images); throws InputError at frame `fail_at` if >= 0.
// exhausted() is ready once it returned its end: by then every frame has arrived.
class ScriptedSource final : public FrameSource {
 public:
  explicit ScriptedSource(std::vector<double> times, int fail_at = -1) : times_(std::move(times)), fail_at_(fail_at) {}
  std::future<void> exhausted() { return exhausted_.get_future(); }
  std::optional<RgbdFrame> Next() override {
    if (next_ == times_.size()) {
      if (!ended_) exhausted_.set_value();
      ended_ = true;
      return std::nullopt;
    }
    if (static_cast<int>(next_) == fail_at_) throw InputError("rgb/broken.png", 0, "cannot decode");
    RgbdFrame frame;
    frame.timestamp = times_[next_++];
    frame.bgr = cv::Mat(1, 1, CV_8UC3, cv::Scalar(1, 2, 3));
    frame.depth_m = cv::Mat(1, 1, CV_32F, cv::Scalar(1.5));
    return frame;
  }
  std::optional<std::size_t> frame_count() const override { return times_.size(); }

 private:
  std::vector<double> times_;
  int fail_at_;
  std::size_t next_ = 0;
  std::promise<void> exhausted_;
  bool ended_ = false;
};

// TUM-like absolute stamps, 0.1 s apart: the playback runs on times relative to the first.
const std::vector<double> kTimes = {1305031102.0, 1305031102.1, 1305031102.2, 1305031102.3, 1305031102.4};

struct Playback {
  std::shared_ptr<ManualPlaybackClock> clock = std::make_shared<ManualPlaybackClock>();
  std::unique_ptr<LivePlaybackSource> source;
  explicit Playback(std::unique_ptr<FrameSource> frames)
      : source(std::make_unique<LivePlaybackSource>(std::move(frames), clock)) {}
  // Moves the clock and waits until every frame due by then has arrived.
  void AdvanceTo(double t_s) {
    clock->AdvanceTo(t_s);
    ASSERT_TRUE(clock->WaitForSleeper());
  }
};

TEST(LivePlaybackSourceTest, ABusyConsumerGetsTheNewestFrameAndTheDropsAreCounted) {
  Playback playback(std::make_unique<ScriptedSource>(kTimes));
  std::optional<RgbdFrame> frame = playback.source->Next();  // starts the clock: frame 0 is due now
  ASSERT_TRUE(frame);
  EXPECT_EQ(frame->timestamp, kTimes[0]);
  EXPECT_EQ(frame->dropped_before, 0);
  EXPECT_EQ(frame->depth_m.at<float>(0, 0), 1.5f);
  playback.AdvanceTo(0.25);  // busy for 2.5 intervals: frames 1 and 2 arrived, 1 was overwritten
  frame = playback.source->Next();
  ASSERT_TRUE(frame);
  EXPECT_EQ(frame->timestamp, kTimes[2]);
  EXPECT_EQ(frame->dropped_before, 1);
  playback.AdvanceTo(0.301);  // in time for frame 3 (relative stamps are exact to ~1e-7 s only)
  frame = playback.source->Next();
  ASSERT_TRUE(frame);
  EXPECT_EQ(frame->timestamp, kTimes[3]);
  EXPECT_EQ(frame->dropped_before, 0);
  playback.clock->AdvanceTo(10);  // the last frame arrives, then the source ends
  frame = playback.source->Next();
  ASSERT_TRUE(frame);
  EXPECT_EQ(frame->timestamp, kTimes[4]);
  EXPECT_FALSE(playback.source->Next());
  EXPECT_FALSE(playback.source->Next());
  EXPECT_EQ(playback.source->frames_dropped(), 1u);
  EXPECT_FALSE(playback.source->frame_count());
}

TEST(LivePlaybackSourceTest, AConsumerBusyPastTheEndStillGetsTheLastFrame) {
  auto frames = std::make_unique<ScriptedSource>(kTimes);
  std::future<void> exhausted = frames->exhausted();
  Playback playback(std::move(frames));
  ASSERT_TRUE(playback.source->Next());
  playback.clock->AdvanceTo(100);
  exhausted.wait();  // frames 1-4 arrived while the consumer was busy
  std::optional<RgbdFrame> frame = playback.source->Next();
  ASSERT_TRUE(frame);
  EXPECT_EQ(frame->timestamp, kTimes[4]);
  EXPECT_EQ(frame->dropped_before, 3);  // returned + dropped = every frame
  EXPECT_FALSE(playback.source->Next());
  EXPECT_EQ(playback.source->frames_dropped(), 3u);
}

TEST(LivePlaybackSourceTest, AConsumerAlwaysReadyDropsNothing) {
  Playback playback(std::make_unique<ScriptedSource>(kTimes));
  for (std::size_t i = 0; i < kTimes.size(); ++i) {
    if (i > 0) playback.clock->AdvanceTo(0.1 * static_cast<double>(i) + 1e-3);
    const std::optional<RgbdFrame> frame = playback.source->Next();  // waits for the frame due
    ASSERT_TRUE(frame);
    EXPECT_EQ(frame->timestamp, kTimes[i]);
    EXPECT_EQ(frame->dropped_before, 0);
  }
  EXPECT_FALSE(playback.source->Next());
  EXPECT_EQ(playback.source->frames_dropped(), 0u);
}

TEST(LivePlaybackSourceTest, ASourceErrorComesAfterTheFramesBeforeIt) {
  Playback playback(std::make_unique<ScriptedSource>(kTimes, 2));
  ASSERT_TRUE(playback.source->Next());
  playback.clock->AdvanceTo(1);
  const std::optional<RgbdFrame> frame = playback.source->Next();
  ASSERT_TRUE(frame);
  EXPECT_EQ(frame->timestamp, kTimes[1]);
  try {
    playback.source->Next();
    FAIL() << "no error";
  } catch (const InputError& e) {  // the wrapped source's own error, type and message
    EXPECT_EQ(e.file(), "rgb/broken.png");
  }
}

TEST(LivePlaybackSourceTest, StoppingMidRunEndsThePlaybackThread) {
  Playback playback(std::make_unique<ScriptedSource>(kTimes));
  ASSERT_TRUE(playback.source->Next());
  ASSERT_TRUE(playback.clock->WaitForSleeper());  // the thread waits for frame 1
  playback.source.reset();                        // interrupts the clock and joins
  EXPECT_FALSE(playback.clock->SleepUntil(1e9));  // interrupted for good
  // Never started: nothing to stop.
  LivePlaybackSource unused(std::make_unique<ScriptedSource>(kTimes), std::make_shared<ManualPlaybackClock>());
}

TEST(LivePlaybackSourceTest, EmptySourceAndMissingParts) {
  Playback playback(std::make_unique<ScriptedSource>(std::vector<double>{}));
  EXPECT_FALSE(playback.source->Next());
  EXPECT_THROW(LivePlaybackSource(nullptr, std::make_shared<ManualPlaybackClock>()), Error);
  EXPECT_THROW(LivePlaybackSource(std::make_unique<ScriptedSource>(kTimes), nullptr), Error);
}

TEST(PlaybackClockTest, SteadyClockSleepsUntilAPastTimeAtOnceAndStopsOnInterrupt) {
  SteadyPlaybackClock clock;
  EXPECT_GE(clock.NowS(), 0.0);
  EXPECT_TRUE(clock.SleepUntil(clock.NowS()));  // already due
  clock.Interrupt();
  EXPECT_FALSE(clock.SleepUntil(1e9));  // would be a day and more; interrupted returns at once
}

}  // namespace
}  // namespace esdslam
