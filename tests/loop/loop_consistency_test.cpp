#include "loop/loop_consistency.h"

#include <gtest/gtest.h>

#include "common/error.h"

namespace esdslam {
namespace {

CandidateGroup Group(long candidate, std::set<long> connected) {
  connected.insert(candidate);
  return {candidate, connected};
}

TEST(LoopConsistencyTest, CandidateBecomesConsistentAfterThresholdConsecutiveQueries) {
  LoopConsistency consistency(3);
  // The revisited place: keyframes 4..8; each query finds a neighbouring candidate there.
  EXPECT_TRUE(consistency.Update({Group(5, {4, 6})}).empty());  // new group, count 0
  EXPECT_TRUE(consistency.Update({Group(6, {5, 7})}).empty());  // 1
  EXPECT_TRUE(consistency.Update({Group(7, {6, 8})}).empty());  // 2
  EXPECT_EQ(consistency.Update({Group(6, {5, 7})}), std::vector<long>{6});  // 3 = threshold
  ASSERT_EQ(consistency.groups().size(), 1u);
  EXPECT_EQ(consistency.groups()[0].consistency, 3);
}

TEST(LoopConsistencyTest, AQueryWithoutTheGroupBreaksTheChain) {
  LoopConsistency consistency(3);
  consistency.Update({Group(5, {4, 6})});
  consistency.Update({Group(6, {5, 7})});
  // An unrelated place interrupts: the old group is dropped, the new one starts at 0.
  EXPECT_TRUE(consistency.Update({Group(40, {41})}).empty());
  ASSERT_EQ(consistency.groups().size(), 1u);
  EXPECT_EQ(consistency.groups()[0].consistency, 0);
  EXPECT_TRUE(consistency.Update({Group(7, {6, 8})}).empty());
  EXPECT_TRUE(consistency.Update({Group(7, {6, 8})}).empty());
  EXPECT_TRUE(consistency.Update({Group(7, {6, 8})}).empty());
  EXPECT_EQ(consistency.Update({Group(7, {6, 8})}), std::vector<long>{7});
  // No candidate at all clears everything.
  EXPECT_TRUE(consistency.Update({}).empty());
  EXPECT_TRUE(consistency.groups().empty());
}

TEST(LoopConsistencyTest, GroupsAreContinuedOnceAndCandidatesReportedOnce) {
  LoopConsistency consistency(1);
  consistency.Update({Group(5, {4}), Group(9, {10})});
  // Candidate 7's group touches both kept groups: reported once; each kept group is continued by
  // the first candidate that touches it only.
  const std::vector<long> enough = consistency.Update({Group(7, {4, 10}), Group(11, {10})});
  EXPECT_EQ(enough, (std::vector<long>{7, 11}));
  ASSERT_EQ(consistency.groups().size(), 2u);  // 7's group twice (once per kept group), 11 none new
  for (const ConsistentGroup& group : consistency.groups()) EXPECT_EQ(group.consistency, 1);
  EXPECT_THROW(LoopConsistency(0), Error);
}

}  // namespace
}  // namespace esdslam
