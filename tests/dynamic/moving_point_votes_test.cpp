// Votes on map points over consecutive frames, and the bounded keyframe depth store.
#include <gtest/gtest.h>

#include "common/error.h"
#include "dynamic/keyframe_depth_store.h"
#include "dynamic/moving_point_votes.h"

namespace esdslam {
namespace {

TEST(MovingPointVotes, CullsAfterConsecutiveEvidenceOnly) {
  MovingPointVotes votes(3);
  for (int frame = 0; frame < 2; ++frame) {
    votes.Evidence(7);
    votes.Evidence(7);  // twice in one frame counts once
    votes.Evidence(9);
    EXPECT_TRUE(votes.EndFrame().empty());
  }
  EXPECT_EQ(votes.count(7), 2);
  votes.Consistent(9);  // measured where it should be: starts again
  votes.EndFrame();     // 7 not tested in this frame: unchanged
  EXPECT_EQ(votes.count(7), 2);
  EXPECT_EQ(votes.count(9), 0);
  votes.Evidence(7);
  votes.Consistent(7);  // evidence wins within a frame
  votes.Evidence(9);
  EXPECT_EQ(votes.EndFrame(), (std::vector<long>{7}));
  EXPECT_EQ(votes.count(7), 0);
  EXPECT_EQ(votes.count(9), 1);
}

TEST(MovingPointVotes, ReturnsIdsInOrderAndForgetsStaleCounts) {
  MovingPointVotes votes(1, 5);
  for (long id : {30L, 4L, 17L}) votes.Evidence(id);
  EXPECT_EQ(votes.EndFrame(), (std::vector<long>{4, 17, 30}));
  MovingPointVotes slow(10, 5);
  slow.Evidence(1);
  slow.EndFrame();
  EXPECT_EQ(slow.size(), 1u);
  for (int i = 0; i < 9; ++i) slow.EndFrame();
  EXPECT_EQ(slow.size(), 0u);
  EXPECT_THROW(MovingPointVotes(0), Error);
}

TEST(KeyframeDepthStore, KeepsScaledDepthOfTheMostRecentlyUsedKeyframes) {
  KeyframeDepthStore store(2, 0.5);
  cv::Mat depth(480, 640, CV_32F, cv::Scalar(2.0f));
  depth(cv::Rect(0, 0, 320, 480)).setTo(0.0f);  // invalid left half stays invalid (no mixing)
  store.Add(1, depth);
  store.Add(2, depth);
  const cv::Mat small = store.Find(1);  // 1 is now used more recently than 2
  ASSERT_EQ(small.size(), cv::Size(320, 240));
  EXPECT_EQ(small.at<float>(100, 159), 0.0f);
  EXPECT_EQ(small.at<float>(100, 160), 2.0f);
  store.Add(3, depth);
  EXPECT_TRUE(store.Contains(1));
  EXPECT_FALSE(store.Contains(2));
  EXPECT_TRUE(store.Find(2).empty());
  EXPECT_EQ(store.bytes(), 2u * 320 * 240 * sizeof(float));
  EXPECT_EQ(store.ids(), (std::vector<long>{1, 3}));
  KeyframeDepthStore none(0, 0.5);
  none.Add(1, depth);
  EXPECT_EQ(none.size(), 0u);
  EXPECT_THROW(KeyframeDepthStore(1, 0), Error);
  EXPECT_THROW(store.Add(4, cv::Mat(4, 4, CV_16U)), Error);
}

}  // namespace
}  // namespace esdslam
