// ScopedLayerConstructor's mutex per layer type: a second registration of a type waits for the
// first to end; registrations of other types do not.
#include "semantic/own_layer.h"

#include <atomic>
#include <chrono>
#include <future>
#include <thread>

#include <gtest/gtest.h>

#include "semantic/concat_layer.h"
#include "semantic/resize_layer.h"

namespace esdslam {
namespace {

using namespace std::chrono_literals;

TEST(ScopedLayerConstructor, SameTypeWaitsForTheFirstScope) {
  std::atomic<bool> registered{false};
  std::thread second;
  {
    ScopedLayerConstructor first("Resize", CreateResizeLayer);
    second = std::thread([&registered] {
      ScopedLayerConstructor scope("Resize", CreateResizeLayer);
      registered = true;
    });
    std::this_thread::sleep_for(100ms);  // time enough for the thread to register, were it not held
    EXPECT_FALSE(registered);
  }
  second.join();
  EXPECT_TRUE(registered);
}

TEST(ScopedLayerConstructor, OtherTypesAreIndependent) {
  std::future<void> other;
  {
    ScopedLayerConstructor resize("Resize", CreateResizeLayer);
    other = std::async(std::launch::async, [] { ScopedLayerConstructor concat("Concat", CreateConcatLayer); });
    // A single registration mutex would hold the thread until this scope ends.
    EXPECT_EQ(other.wait_for(30s), std::future_status::ready);
  }
  other.get();
}

}  // namespace
}  // namespace esdslam
