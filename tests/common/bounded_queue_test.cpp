#include "common/bounded_queue.h"

#include <thread>

#include <gtest/gtest.h>

namespace esdslam {
namespace {

TEST(BoundedQueue, DeliversInOrderAcrossThreads) {
  BoundedQueue<int> queue(2);
  std::thread producer([&] {
    for (int i = 0; i < 100; ++i) queue.Push(i);
    queue.Close();
  });
  int expected = 0;
  while (auto item = queue.Pop()) EXPECT_EQ(*item, expected++);
  producer.join();
  EXPECT_EQ(expected, 100);
}

TEST(BoundedQueue, DropOldestKeepsNewest) {
  BoundedQueue<int> queue(1);
  EXPECT_EQ(queue.PushDropOldest(1), DropOldestPush::kQueued);
  EXPECT_EQ(queue.PushDropOldest(2), DropOldestPush::kQueuedDroppedOldest);
  EXPECT_EQ(queue.Size(), 1u);
  EXPECT_EQ(*queue.TryPop(), 2);
}

TEST(BoundedQueue, PushFailsAfterClose) {
  BoundedQueue<int> queue(1);
  queue.Close();
  EXPECT_FALSE(queue.Push(1));
  EXPECT_EQ(queue.PushDropOldest(1), DropOldestPush::kClosed);
  EXPECT_FALSE(queue.Pop().has_value());
}

}  // namespace
}  // namespace esdslam
