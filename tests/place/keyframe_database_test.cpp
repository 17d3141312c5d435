#include "place/keyframe_database.h"

#include <gtest/gtest.h>

#include "common/error.h"
#include "place/vocabulary.h"
#include "synthetic_descriptors.h"

namespace esdslam {
namespace {

using test::ObserveLandmarks;
using test::RandomDescriptors;

// A corridor of 40 keyframes: keyframe i observes landmarks [50 i, 50 i + 250); the covisibility
// graph links keyframes up to 2 apart. Landmarks 2000..2999 are never seen by the keyframes.
class KeyFrameDatabaseTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::mt19937 rng(21);
    landmarks_ = RandomDescriptors(3000, &rng);
    std::vector<cv::Mat> keyframe_descriptors;
    for (int i = 0; i < 40; ++i) keyframe_descriptors.push_back(ObserveLandmarks(landmarks_, 50 * i, 250, 8, &rng));
    VocabularyOptions options;
    options.branching = 8;
    options.levels = 3;
    vocabulary_ = Vocabulary::Train(keyframe_descriptors, options);
    for (int i = 0; i < 40; ++i) database_.Add(i, vocabulary_.Transform(keyframe_descriptors[i]));
  }

  static std::vector<long> Neighbours(long id) {
    std::vector<long> out;
    for (long j = id - 2; j <= id + 2; ++j) {
      if (j != id && j >= 0 && j < 40) out.push_back(j);
    }
    return out;
  }

  BowVector Observe(int first, int count, std::uint32_t seed) {
    std::mt19937 rng(seed);
    return vocabulary_.Transform(ObserveLandmarks(landmarks_, first, count, 8, &rng));
  }

  cv::Mat landmarks_;
  Vocabulary vocabulary_;
  KeyFrameDatabase database_;
};

TEST_F(KeyFrameDatabaseTest, RelocalizationFindsTheRevisitedPlace) {
  // A frame seeing exactly what keyframe 17 saw (fresh descriptor noise).
  const std::vector<PlaceCandidate> candidates = database_.DetectRelocalizationCandidates(Observe(850, 250, 99), Neighbours);
  ASSERT_FALSE(candidates.empty());
  EXPECT_EQ(candidates.front().keyframe_id, 17);
  for (const PlaceCandidate& c : candidates) EXPECT_NEAR(c.keyframe_id, 17, 2);
}

TEST_F(KeyFrameDatabaseTest, LoopCandidateExcludesConnectedAndRespectsMinScore) {
  // Query keyframe 41 (not in the database yet) revisits keyframe 8's place; its covisible
  // neighbours 39, 40 and the query are excluded. It also sees 150 unrelated landmarks.
  cv::Mat descriptors;
  std::mt19937 rng(5);
  cv::vconcat(ObserveLandmarks(landmarks_, 400, 250, 8, &rng), ObserveLandmarks(landmarks_, 2000, 150, 8, &rng),
              descriptors);
  const BowVector query = vocabulary_.Transform(descriptors);
  const std::set<long> excluded{39, 40, 41};
  const double min_score = database_.MinScore(query, {39});
  const std::vector<PlaceCandidate> candidates = database_.DetectLoopCandidates(query, excluded, min_score, Neighbours);
  ASSERT_FALSE(candidates.empty());
  EXPECT_EQ(candidates.front().keyframe_id, 8);
  for (const PlaceCandidate& c : candidates) {
    EXPECT_EQ(excluded.count(c.keyframe_id), 0u);
    EXPECT_GE(c.score, min_score);
    EXPECT_GE(c.accumulated_score, c.score);
  }
  // A min score above every candidate's score leaves nothing.
  EXPECT_TRUE(database_.DetectLoopCandidates(query, excluded, 0.99, Neighbours).empty());
}

TEST_F(KeyFrameDatabaseTest, EraseRemovesKeyframeFromResults) {
  const BowVector query = Observe(850, 250, 7);
  database_.Erase(17);
  EXPECT_FALSE(database_.Contains(17));
  EXPECT_EQ(database_.size(), 39u);
  const std::vector<PlaceCandidate> candidates = database_.DetectRelocalizationCandidates(query, Neighbours);
  ASSERT_FALSE(candidates.empty());
  for (const PlaceCandidate& c : candidates) EXPECT_NE(c.keyframe_id, 17);
  EXPECT_NEAR(candidates.front().keyframe_id, 17, 1);
  database_.Clear();
  EXPECT_TRUE(database_.DetectRelocalizationCandidates(query, Neighbours).empty());
}

TEST_F(KeyFrameDatabaseTest, MinScoreSeparatesRevisitFromUnrelated) {
  // With this small vocabulary (<= 512 words) unrelated images still share words by chance, but
  // the lowest score of a true revisit against its place stays well above it.
  const double unrelated = database_.MinScore(Observe(2000, 250, 3), {16, 17, 18});
  const double revisit = database_.MinScore(Observe(850, 250, 3), {16, 17, 18});
  EXPECT_GT(revisit, 2.0 * unrelated);
  EXPECT_DOUBLE_EQ(database_.MinScore(Observe(850, 250, 3), {}), 1.0);
}

TEST(KeyFrameDatabaseOptionsTest, RejectsInvalidRatios) {
  KeyFrameDatabaseOptions options;
  options.group_score_ratio = 0.0;
  EXPECT_THROW(KeyFrameDatabase{options}, Error);
}

}  // namespace
}  // namespace esdslam
