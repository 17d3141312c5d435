// Which frames the network labels and when their labels are used (dynamic/label_schedule.h).
#include <gtest/gtest.h>

#include "common/error.h"
#include "dynamic/label_schedule.h"

namespace esdslam {
namespace {

LabelSchedule Schedule(int every, int delay, bool newest_wins = false) {
  LabelScheduleOptions options;
  options.segment_every = every;
  options.label_delay_frames = delay;
  options.newest_wins = newest_wins;
  return LabelSchedule(options);
}

// Frames 0, 4, 8, ... go to the network when it is free by then; labels are used 2 frames later.
TEST(LabelScheduleTest, EveryKthFrameWithItsLabelsUsedAfterTheDelay) {
  LabelSchedule schedule = Schedule(4, 2);
  EXPECT_EQ(schedule.label_delay(), 2);
  std::vector<std::int64_t> submitted;
  for (std::int64_t id = 0; id < 13; ++id) {
    if (schedule.Submit(id, false)) submitted.push_back(id);
    if (schedule.in_flight() && id >= *schedule.in_flight() + 1) schedule.Done();  // back one frame later
  }
  EXPECT_EQ(submitted, (std::vector<std::int64_t>{0, 4, 8, 12}));
}

// One frame in flight at most: a K-th frame that comes while the network is busy is owed and
// the first frame after the network is free goes instead.
TEST(LabelScheduleTest, BusyNetworkDefersTheScheduledFrame) {
  LabelSchedule schedule = Schedule(2, 1);
  EXPECT_TRUE(schedule.Submit(0, false));
  EXPECT_FALSE(schedule.Submit(1, false));
  EXPECT_FALSE(schedule.Submit(2, false));  // busy: owed
  EXPECT_FALSE(schedule.Submit(3, false));
  schedule.Done();                         // labels of 0 back late
  EXPECT_TRUE(schedule.Submit(5, false));  // the owed frame: the next one
  EXPECT_EQ(schedule.in_flight(), 5);
}

TEST(LabelScheduleTest, UntrustedPredictionAsksForLabelsEarly) {
  LabelSchedule schedule = Schedule(8, 2);
  EXPECT_TRUE(schedule.Submit(0, false));
  schedule.Done();
  EXPECT_FALSE(schedule.Submit(1, false));
  EXPECT_TRUE(schedule.Submit(2, true));  // needs labels, network free
  EXPECT_FALSE(schedule.Submit(3, true)); // busy
}

TEST(LabelScheduleTest, NewestWinsTakesAFrameWheneverFreeAndUsesLabelsAtOnce) {
  LabelSchedule schedule = Schedule(4, 3, true);
  EXPECT_TRUE(schedule.Submit(0, false));
  EXPECT_EQ(schedule.label_delay(), 0);  // labels used at once
  EXPECT_FALSE(schedule.Submit(1, false));
  schedule.Done();
  EXPECT_TRUE(schedule.Submit(2, false));
}

TEST(LabelScheduleTest, RejectsBadOptionsAndIdsThatDoNotIncrease) {
  EXPECT_THROW(Schedule(0, 2), Error);
  EXPECT_THROW(Schedule(4, -1), Error);
  EXPECT_THROW(Schedule(1001, 2), Error);
  LabelSchedule schedule = Schedule(4, 2);
  schedule.Submit(3, false);
  EXPECT_THROW(schedule.Submit(3, false), Error);
}

}  // namespace
}  // namespace esdslam
