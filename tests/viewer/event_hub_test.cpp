#include "viewer/event_hub.h"

#include <chrono>
#include <thread>

#include <gtest/gtest.h>

namespace esdslam {
namespace {

using std::chrono::milliseconds;

TEST(EventHub, ASlowReaderGetsOnlyTheNewestEventOfEachName) {
  EventHub hub;
  hub.Publish("frame", "1");
  hub.Publish("map", "m1");
  hub.Publish("frame", "2");
  hub.Publish("frame", "3");
  std::uint64_t seen = 0;
  const std::vector<HubEvent> events = hub.WaitNewer(&seen, milliseconds(0));
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].name, "map");  // in publication order of the kept ones
  EXPECT_EQ(events[0].data, "m1");
  EXPECT_EQ(events[1].name, "frame");
  EXPECT_EQ(events[1].data, "3");
  EXPECT_EQ(seen, 4u);
  EXPECT_EQ(hub.published(), 4u);
  EXPECT_EQ(hub.unread_replaced(), 2u);  // frames 1 and 2 were never read
  hub.Publish("frame", "4");             // replaces one that was read: not a drop
  EXPECT_EQ(hub.unread_replaced(), 2u);
}

TEST(EventHub, WaitTimesOutWithNothingNewAndReturnsOnlyNewerEvents) {
  EventHub hub;
  hub.Publish("frame", "1");
  std::uint64_t seen = 0;
  ASSERT_EQ(hub.WaitNewer(&seen, milliseconds(0)).size(), 1u);
  EXPECT_TRUE(hub.WaitNewer(&seen, milliseconds(5)).empty());
  hub.Publish("status", "s");
  const std::vector<HubEvent> events = hub.WaitNewer(&seen, milliseconds(0));
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].name, "status");
}

TEST(EventHub, ANewEventOrCloseWakesAWaitingReader) {
  EventHub hub;
  std::uint64_t seen = 0;
  std::vector<HubEvent> got;
  std::thread reader([&] { got = hub.WaitNewer(&seen, milliseconds(60000)); });
  hub.Publish("frame", "x");
  reader.join();
  ASSERT_EQ(got.size(), 1u);
  std::thread closed_reader([&] { got = hub.WaitNewer(&seen, milliseconds(60000)); });
  hub.Close();
  closed_reader.join();
  EXPECT_TRUE(got.empty());
  EXPECT_TRUE(hub.closed());
  hub.Publish("frame", "after close");
  EXPECT_EQ(hub.Latest().size(), 1u);
}

TEST(EventHub, FormatsServerSentEventsAndASnapshotObject) {
  HubEvent event{"frame", "{\"a\":1}", 7};
  EXPECT_EQ(FormatServerSentEvent(event), "event: frame\ndata: {\"a\":1}\n\n");
  HubEvent other{"map", "[]", 8};
  EXPECT_EQ(EventsAsJson({event, other}), "{\"frame\":{\"a\":1},\"map\":[]}");
  EXPECT_EQ(EventsAsJson({}), "{}");
}

}  // namespace
}  // namespace esdslam
