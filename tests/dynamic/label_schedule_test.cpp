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

// Frames 0, 4, 8, ... go to the network; each one's labels are due 2 frames later, and the
// network is free again once they are used.
TEST(LabelScheduleTest, EveryKthFrameWithItsLabelsDueAfterTheDelay) {
  LabelSchedule schedule = Schedule(4, 2);
  std::vector<std::int64_t> submitted;
  for (std::int64_t id = 0; id < 13; ++id) {
    if (schedule.Submit(id, false)) submitted.push_back(id);
    const std::optional<std::int64_t> due = schedule.Due(id);
    if (schedule.in_flight()) {
      const std::int64_t s = *schedule.in_flight();
      EXPECT_EQ(due.has_value(), id >= s + 2) << id;
    }
    if (due) schedule.Done();
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
  EXPECT_FALSE(schedule.Due(5).has_value());
  EXPECT_EQ(schedule.Due(6), 5);
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
  EXPECT_EQ(schedule.Due(0), 0);  // no delay
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
