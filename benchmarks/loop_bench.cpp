// Place-recognition benchmarks: vocabulary training (small synthetic set), loading the shipped
// vocabulary, BoW transform of one 1000-feature frame, keyframe-database queries.
#include <filesystem>
#include <random>

#include <benchmark/benchmark.h>
#include <opencv2/imgcodecs.hpp>

#include "feature/orb_extractor.h"
#include "place/keyframe_database.h"
#include "place/vocabulary.h"

namespace esdslam {
namespace {

const std::string kShippedVocabulary = std::string(ESDSLAM_SOURCE_DIR) + "/models/vocabulary/orb_vocabulary.bin";

cv::Mat RandomRows(int rows, std::mt19937* rng) {
  cv::Mat out(rows, 32, CV_8U);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < 32; ++c) out.at<unsigned char>(r, c) = static_cast<unsigned char>((*rng)() & 0xFF);
  return out;
}

// 1000 ORB descriptors of a real TUM frame when the data is present, random rows otherwise.
cv::Mat FrameDescriptors() {
  const std::string path = std::string(ESDSLAM_TEST_DATA_DIR) + "/data/tum_fr1_rpy_dev/rgb";
  if (std::filesystem::is_directory(path)) {
    std::vector<std::string> files;
    for (const auto& entry : std::filesystem::directory_iterator(path)) files.push_back(entry.path().string());
    std::sort(files.begin(), files.end());
    const cv::Mat gray = cv::imread(files.front(), cv::IMREAD_GRAYSCALE);
    std::vector<cv::KeyPoint> keypoints;
    cv::Mat descriptors;
    OrbExtractor(OrbOptions()).Extract(gray, cv::Mat(), &keypoints, &descriptors);
    return descriptors;
  }
  std::mt19937 rng(1);
  return RandomRows(1000, &rng);
}

void BM_VocabularyTrainSmall(benchmark::State& state) {
  // 50 images x 500 descriptors, k = 10, L = 3.
  std::mt19937 rng(3);
  std::vector<cv::Mat> images;
  for (int i = 0; i < 50; ++i) images.push_back(RandomRows(500, &rng));
  VocabularyOptions options;
  options.levels = 3;
  for (auto _ : state) benchmark::DoNotOptimize(Vocabulary::Train(images, options).num_words());
}
BENCHMARK(BM_VocabularyTrainSmall)->Unit(benchmark::kMillisecond);

void BM_VocabularyLoadShipped(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(Vocabulary::Load(kShippedVocabulary).num_words());
}
BENCHMARK(BM_VocabularyLoadShipped)->Unit(benchmark::kMillisecond);

void BM_BowTransform1000(benchmark::State& state) {
  const Vocabulary vocabulary = Vocabulary::Load(kShippedVocabulary);
  const cv::Mat descriptors = FrameDescriptors();
  FeatureVector direct;
  for (auto _ : state) benchmark::DoNotOptimize(vocabulary.Transform(descriptors, &direct, 2).size());
  state.counters["features"] = descriptors.rows;
}
BENCHMARK(BM_BowTransform1000)->Unit(benchmark::kMicrosecond);

void BM_DatabaseQuery(benchmark::State& state) {
  // state.range(0) keyframes, each the BoW of 1000 random descriptors (worst case for the
  // inverted index: words spread evenly).
  const Vocabulary vocabulary = Vocabulary::Load(kShippedVocabulary);
  std::mt19937 rng(5);
  KeyFrameDatabase database;
  for (long id = 0; id < state.range(0); ++id) database.Add(id, vocabulary.Transform(RandomRows(1000, &rng)));
  const BowVector query = vocabulary.Transform(FrameDescriptors());
  const auto neighbours = [](long id) { return std::vector<long>{id - 1, id + 1}; };
  for (auto _ : state) benchmark::DoNotOptimize(database.DetectRelocalizationCandidates(query, neighbours).size());
}
BENCHMARK(BM_DatabaseQuery)->Arg(100)->Arg(500)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace esdslam

BENCHMARK_MAIN();
