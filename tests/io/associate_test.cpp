#include "io/associate.h"

#include <gtest/gtest.h>

namespace esdslam {
namespace {

std::vector<std::pair<std::size_t, std::size_t>> Pairs(const std::vector<TimestampMatch>& matches) {
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  for (const auto& m : matches) pairs.emplace_back(m.first, m.second);
  return pairs;
}

using PairList = std::vector<std::pair<std::size_t, std::size_t>>;

TEST(Associate, BoundaryOfMaxDifferenceIsInclusive) {
  // 1.02 - 1.00 is 0.020000000000000018 in binary: still a match; 0.0201 is not.
  EXPECT_EQ(Pairs(AssociateTimestamps({1.00}, {1.02}, 0.02)), (PairList{{0, 0}}));
  EXPECT_EQ(Pairs(AssociateTimestamps({1.02}, {1.00}, 0.02)), (PairList{{0, 0}}));
  EXPECT_TRUE(AssociateTimestamps({1.00}, {1.0201}, 0.02).empty());
  EXPECT_TRUE(AssociateTimestamps({1.00}, {0.9799}, 0.02).empty());
}

TEST(Associate, GreedyBySmallestDifferenceEachUsedOnce) {
  // Depth 0 (t=1.005) is closest to rgb 0 (1.000, dt 0.005) and rgb 1 (1.008, dt 0.003):
  // greedy gives it to rgb 1; rgb 0 then takes nothing else within 0.02 except depth 1 (1.019).
  const std::vector<double> rgb = {1.000, 1.008, 2.000};
  const std::vector<double> depth = {1.005, 1.019, 3.000};
  EXPECT_EQ(Pairs(AssociateTimestamps(rgb, depth, 0.02)), (PairList{{0, 1}, {1, 0}}));
}

TEST(Associate, ResultSortedByFirstTimeAndInputNeedNotBeSorted) {
  const std::vector<double> first = {3.0, 1.0, 2.0};
  const std::vector<double> second = {2.001, 0.999, 3.002};
  EXPECT_EQ(Pairs(AssociateTimestamps(first, second, 0.02)), (PairList{{1, 1}, {2, 0}, {0, 2}}));
}

TEST(Associate, OffsetIsAddedToSecondTimes) {
  // |t_a - (t_b + offset)| <= max: 1.0 vs 0.5 + 0.5.
  EXPECT_EQ(Pairs(AssociateTimestamps({1.0}, {0.5}, 0.02, 0.5)), (PairList{{0, 0}}));
  EXPECT_TRUE(AssociateTimestamps({1.0}, {0.5}, 0.02, 0.0).empty());
}

TEST(Associate, TiesPreferEarlierFirstElement) {
  // Second 1.25 is exactly 0.25 from both 1.0 and 1.5: the earlier first element wins.
  EXPECT_EQ(Pairs(AssociateTimestamps({1.0, 1.5}, {1.25}, 0.3)), (PairList{{0, 0}}));
  EXPECT_EQ(Pairs(AssociateTimestamps({1.5, 1.0}, {1.25}, 0.3)), (PairList{{1, 0}}));
}

TEST(Associate, EmptyInputs) {
  EXPECT_TRUE(AssociateTimestamps({}, {1.0}, 0.02).empty());
  EXPECT_TRUE(AssociateTimestamps({1.0}, {}, 0.02).empty());
}

}  // namespace
}  // namespace esdslam
