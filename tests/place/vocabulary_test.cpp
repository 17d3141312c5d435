#include "place/vocabulary.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include <gtest/gtest.h>

#include "common/error.h"
#include "synthetic_descriptors.h"
#include "support/temp_path.h"

namespace esdslam {
namespace {

using test::ObserveLandmarks;
using test::RandomDescriptors;

// 1200 landmarks; training image i observes a window of 300 starting at 40 i (30 images).
struct LandmarkWorld {
  LandmarkWorld() : rng(7), landmarks(RandomDescriptors(1200, &rng)) {
    for (int i = 0; i < 30; ++i) training.push_back(ObserveLandmarks(landmarks, 40 * i, 300, 8, &rng));
  }
  std::mt19937 rng;
  cv::Mat landmarks;
  std::vector<cv::Mat> training;
};

VocabularyOptions SmallOptions() {
  VocabularyOptions options;
  options.branching = 8;
  options.levels = 3;
  options.seed = 3;
  return options;
}

std::string TempPath(const std::string& name) {
  return testing::TestTempPath("loop_" + name);
}

TEST(VocabularyTest, WordsSeparateKnownClusters) {
  // 20 well separated cluster centres (random: ~128 bits apart), members within 10 bits.
  std::mt19937 rng(11);
  const cv::Mat centres = RandomDescriptors(20, &rng);
  std::vector<cv::Mat> images;
  for (int image = 0; image < 10; ++image) images.push_back(ObserveLandmarks(centres, 0, 20 * 30, 10, &rng));
  VocabularyOptions options;
  options.branching = 10;
  options.levels = 2;
  const Vocabulary vocabulary = Vocabulary::Train(images, options);
  // Every word is reached by members of one cluster only.
  std::map<WordId, std::set<int>> clusters_of_word;
  const cv::Mat probe = ObserveLandmarks(centres, 0, 20 * 50, 10, &rng);
  for (int r = 0; r < probe.rows; ++r) {
    const WordId word = vocabulary.Quantize(DescriptorFromBytes(probe.ptr<unsigned char>(r)));
    clusters_of_word[word].insert(r % 20);
  }
  std::set<WordId> words_used;
  for (const auto& [word, clusters] : clusters_of_word) {
    EXPECT_EQ(clusters.size(), 1u) << "word " << word << " mixes clusters";
    words_used.insert(word);
  }
  EXPECT_GE(words_used.size(), 20u);
}

TEST(VocabularyTest, TreeShapeAndWeights) {
  const LandmarkWorld world;
  const Vocabulary vocabulary = Vocabulary::Train(world.training, SmallOptions());
  EXPECT_EQ(vocabulary.branching(), 8);
  EXPECT_EQ(vocabulary.levels(), 3);
  EXPECT_GT(vocabulary.num_words(), 200);
  EXPECT_LE(vocabulary.num_words(), 8 * 8 * 8);
  for (WordId w = 0; w < vocabulary.num_words(); ++w) {
    EXPECT_GE(vocabulary.word_weight(w), 0.0);
    EXPECT_LE(vocabulary.word_weight(w), std::log(30.0) + 1e-12);
  }
}

TEST(VocabularyTest, TransformIsNormalisedSortedAndScoresAsDefined) {
  const LandmarkWorld world;
  const Vocabulary vocabulary = Vocabulary::Train(world.training, SmallOptions());
  std::mt19937 rng(5);
  const BowVector a = vocabulary.Transform(ObserveLandmarks(world.landmarks, 0, 300, 8, &rng));
  const BowVector b = vocabulary.Transform(ObserveLandmarks(world.landmarks, 150, 300, 8, &rng));
  double sum = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    sum += a[i].weight;
    EXPECT_GT(a[i].weight, 0.0);
    if (i > 0) {
      EXPECT_LT(a[i - 1].word, a[i].word);
    }
  }
  EXPECT_NEAR(sum, 1.0, 1e-12);
  // s = 1 - 0.5 * |a - b|_1 computed densely.
  std::vector<double> dense_a(vocabulary.num_words(), 0.0), dense_b(vocabulary.num_words(), 0.0);
  for (const BowEntry& e : a) dense_a[e.word] = e.weight;
  for (const BowEntry& e : b) dense_b[e.word] = e.weight;
  double l1 = 0.0;
  for (int w = 0; w < vocabulary.num_words(); ++w) l1 += std::abs(dense_a[w] - dense_b[w]);
  EXPECT_NEAR(vocabulary.Score(a, b), 1.0 - 0.5 * l1, 1e-12);
}

TEST(VocabularyTest, OverlappingViewScoresHigherThanUnrelated) {
  const LandmarkWorld world;
  const Vocabulary vocabulary = Vocabulary::Train(world.training, SmallOptions());
  std::mt19937 rng(9);
  const BowVector query = vocabulary.Transform(ObserveLandmarks(world.landmarks, 100, 300, 8, &rng));
  const BowVector overlapping = vocabulary.Transform(ObserveLandmarks(world.landmarks, 200, 300, 8, &rng));
  const BowVector unrelated = vocabulary.Transform(ObserveLandmarks(world.landmarks, 700, 300, 8, &rng));
  EXPECT_NEAR(vocabulary.Score(query, query), 1.0, 1e-12);
  const double s_overlap = vocabulary.Score(query, overlapping);
  const double s_unrelated = vocabulary.Score(query, unrelated);
  EXPECT_GT(s_overlap, 0.3);
  EXPECT_GT(s_overlap, 2.0 * s_unrelated);
}

TEST(VocabularyTest, DirectIndexGroupsEveryFeatureUnderANodeOfTheLevel) {
  const LandmarkWorld world;
  const Vocabulary vocabulary = Vocabulary::Train(world.training, SmallOptions());
  std::mt19937 rng(2);
  const cv::Mat descriptors = ObserveLandmarks(world.landmarks, 0, 300, 8, &rng);
  FeatureVector direct;
  vocabulary.Transform(descriptors, &direct, 2);
  std::vector<int> seen(descriptors.rows, 0);
  for (const auto& [node, features] : direct) {
    EXPECT_LE(vocabulary.node_depth(node), 2);
    for (const int f : features) ++seen[f];
  }
  for (const int count : seen) EXPECT_EQ(count, 1);
  EXPECT_GT(direct.size(), 10u);
  EXPECT_THROW(vocabulary.Transform(descriptors, &direct, 4), Error);
}

TEST(VocabularyTest, TrainingIsDeterministicAndSaveLoadRoundTrips) {
  const LandmarkWorld world;
  const Vocabulary first = Vocabulary::Train(world.training, SmallOptions());
  const Vocabulary second = Vocabulary::Train(world.training, SmallOptions());
  const std::string path_a = TempPath("voc_a.bin"), path_b = TempPath("voc_b.bin");
  first.Save(path_a);
  second.Save(path_b);
  std::ifstream in_a(path_a, std::ios::binary), in_b(path_b, std::ios::binary);
  const std::string bytes_a((std::istreambuf_iterator<char>(in_a)), {});
  const std::string bytes_b((std::istreambuf_iterator<char>(in_b)), {});
  EXPECT_EQ(bytes_a, bytes_b);

  const Vocabulary loaded = Vocabulary::Load(path_a);
  EXPECT_EQ(loaded.num_words(), first.num_words());
  EXPECT_EQ(loaded.num_nodes(), first.num_nodes());
  std::mt19937 rng(4);
  for (int trial = 0; trial < 3; ++trial) {
    const cv::Mat descriptors = ObserveLandmarks(world.landmarks, 333 * trial, 300, 12, &rng);
    FeatureVector direct_original, direct_loaded;
    const BowVector original = first.Transform(descriptors, &direct_original, 1);
    const BowVector reloaded = loaded.Transform(descriptors, &direct_loaded, 1);
    ASSERT_EQ(original.size(), reloaded.size());
    for (std::size_t i = 0; i < original.size(); ++i) {
      EXPECT_EQ(original[i].word, reloaded[i].word);
      EXPECT_EQ(original[i].weight, reloaded[i].weight);
    }
    EXPECT_EQ(direct_original, direct_loaded);
  }
  std::remove(path_a.c_str());
  std::remove(path_b.c_str());
}

TEST(VocabularyTest, CorruptFilesThrowInputError) {
  const LandmarkWorld world;
  const std::string path = TempPath("voc_corrupt.bin");
  Vocabulary::Train(world.training, SmallOptions()).Save(path);
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), {});
  in.close();
  const auto write = [&](const std::string& content) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(content.data(), static_cast<std::streamsize>(content.size()));
  };
  write(bytes.substr(0, bytes.size() / 2));  // truncated
  EXPECT_THROW(Vocabulary::Load(path), InputError);
  write(bytes.substr(0, 10));  // truncated inside the header
  EXPECT_THROW(Vocabulary::Load(path), InputError);
  std::string flipped = bytes;
  flipped[bytes.size() / 2] ^= 0x10;  // one flipped bit in the node table
  write(flipped);
  EXPECT_THROW(Vocabulary::Load(path), InputError);
  std::string wrong_magic = bytes;
  wrong_magic[0] = 'X';
  write(wrong_magic);
  EXPECT_THROW(Vocabulary::Load(path), InputError);
  std::remove(path.c_str());
  EXPECT_THROW(Vocabulary::Load(path), InputError);  // missing
}

TEST(VocabularyTest, RejectsInvalidOptionsAndDescriptors) {
  VocabularyOptions options;
  options.branching = 1;
  EXPECT_THROW(options.Check(), Error);
  options = VocabularyOptions();
  options.levels = 0;
  EXPECT_THROW(options.Check(), Error);
  EXPECT_THROW(Vocabulary::Train({cv::Mat(10, 16, CV_8U, cv::Scalar(0))}, VocabularyOptions()), Error);
  EXPECT_THROW(Vocabulary::Train({}, VocabularyOptions()), Error);
}

}  // namespace
}  // namespace esdslam
