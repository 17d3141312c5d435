// Shipped vocabulary on real frames (reads ../shared). The vocabulary was trained on the TUM
// fr1_rpy frames and synthetic images, never on Bonn: the Bonn checks are on held-out images.
#include <chrono>
#include <cstdlib>
#include <filesystem>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "feature/orb_extractor.h"
#include "place/keyframe_database.h"
#include "place/vocabulary.h"
#include "place/vocabulary_images.h"
#include "support/test_paths.h"

namespace esdslam {
namespace {

const std::string kVocabularyPath = ::esdslam::testing::SourceDir() + "/models/vocabulary/orb_vocabulary.bin";

class ShippedVocabularyTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::string data = ::esdslam::testing::TestDataDir() + "/data";
    if (!std::filesystem::is_directory(data + "/tum_fr1_rpy_dev") || !std::filesystem::is_directory(data + "/bonn_crowd_dev"))
      GTEST_SKIP() << "no real sequences in " << data;
    const auto start = std::chrono::steady_clock::now();
    vocabulary_ = Vocabulary::Load(kVocabularyPath);
    load_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    tum_ = ListTrainingImages({data + "/tum_fr1_rpy_dev"});
    bonn_ = ListTrainingImages({data + "/bonn_crowd_dev"});
  }

  BowVector Bow(const std::string& path) const {
    std::vector<cv::Mat> descriptors = ExtractTrainingDescriptors({path}, OrbOptions());
    return vocabulary_.Transform(descriptors.front());
  }

  Vocabulary vocabulary_;
  double load_seconds_ = 0.0;
  std::vector<std::string> tum_, bonn_;
};

TEST_F(ShippedVocabularyTest, LoadsFastAndHasTheDocumentedShape) {
  EXPECT_LT(load_seconds_, 0.5);
  EXPECT_EQ(vocabulary_.branching(), 10);
  EXPECT_GT(vocabulary_.num_words(), 5000);
}

// Frame i vs i + 2 (overlapping view) vs a frame of the other sequence (different room), on the
// training sequence (TUM) and on held-out frames (Bonn, shared scene despite moving people).
TEST_F(ShippedVocabularyTest, NeighbourFramesScoreHigherThanAnotherRoom) {
  ASSERT_GE(tum_.size(), 100u);
  ASSERT_GE(bonn_.size(), 200u);
  // Measured with the shipped vocabulary: s(i, i+2) 0.09-0.21, across rooms 0.035-0.066.
  double sum_next = 0.0, sum_across = 0.0;
  for (int i = 0; i < 100; i += 25) {
    const BowVector tum = Bow(tum_[i]);
    const BowVector bonn = Bow(bonn_[2 * i]);
    EXPECT_NEAR(vocabulary_.Score(tum, tum), 1.0, 1e-12);
    const double tum_next = vocabulary_.Score(tum, Bow(tum_[i + 2]));
    const double bonn_next = vocabulary_.Score(bonn, Bow(bonn_[2 * i + 2]));
    const double across = vocabulary_.Score(tum, bonn);
    EXPECT_GT(tum_next, 1.2 * across) << "TUM frame " << i;
    EXPECT_GT(bonn_next, 1.2 * across) << "Bonn frame " << 2 * i;
    sum_next += tum_next + bonn_next;
    sum_across += 2.0 * across;
  }
  EXPECT_GT(sum_next, 2.5 * sum_across);
}

// Keyframes every 10th frame of the held-out Bonn window; frames between them relocalize to an
// adjacent keyframe.
TEST_F(ShippedVocabularyTest, RelocalizationOnHeldOutFramesFindsAdjacentKeyframe) {
  KeyFrameDatabase database;
  for (long k = 0; k < 25; ++k) database.Add(10 * k, Bow(bonn_[10 * k]));
  const auto neighbours = [](long id) { return std::vector<long>{id - 10, id + 10}; };
  for (const int frame : {33, 87, 124, 166, 203}) {
    const std::vector<PlaceCandidate> candidates = database.DetectRelocalizationCandidates(Bow(bonn_[frame]), neighbours);
    ASSERT_FALSE(candidates.empty()) << frame;
    EXPECT_LE(std::abs(candidates.front().keyframe_id - frame), 10) << "frame " << frame;
  }
}

}  // namespace
}  // namespace esdslam
