// ORB extraction time per frame on the real dev sequences (../shared/data).
//   build-<you>/benchmarks/feature_bench [--benchmark_filter=...]
#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "feature/orb_extractor.h"

namespace {

// First `count` frames (by file name = timestamp) of a sequence, as gray images.
std::vector<cv::Mat> LoadGrayFrames(const std::string& sequence, int count) {
  const std::filesystem::path dir = std::filesystem::path(ESDSLAM_TEST_DATA_DIR) / "data" / sequence / "rgb";
  std::vector<std::filesystem::path> files;
  if (!std::filesystem::is_directory(dir)) return {};
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    if (entry.path().extension() == ".png") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  std::vector<cv::Mat> frames;
  for (int i = 0; i < std::min<int>(count, static_cast<int>(files.size())); ++i) {
    cv::Mat gray;
    cv::cvtColor(cv::imread(files[i].string(), cv::IMREAD_COLOR), gray, cv::COLOR_BGR2GRAY);
    frames.push_back(gray);
  }
  return frames;
}

void RunExtraction(benchmark::State& state, const std::string& sequence, bool masked) {
  const std::vector<cv::Mat> frames = LoadGrayFrames(sequence, 40);
  if (frames.empty()) {
    state.SkipWithError("sequence not found under ESDSLAM_TEST_DATA_DIR");
    return;
  }
  cv::Mat mask;
  if (masked) {  // people on 70% of the image: only a right-hand band is static
    mask = cv::Mat::zeros(frames[0].size(), CV_8U);
    const int allowed_from = frames[0].cols * 7 / 10;
    mask(cv::Rect(allowed_from, 0, frames[0].cols - allowed_from, frames[0].rows)).setTo(255);
  }
  const esdslam::OrbExtractor extractor(esdslam::OrbOptions{});
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  size_t frame = 0, total_keypoints = 0;
  for (auto _ : state) {
    extractor.Extract(frames[frame], mask, &keypoints, &descriptors);
    total_keypoints += keypoints.size();
    frame = (frame + 1) % frames.size();
  }
  state.counters["keypoints"] =
      benchmark::Counter(static_cast<double>(total_keypoints), benchmark::Counter::kAvgIterations);
}

void BM_OrbExtractTumRpy(benchmark::State& state) { RunExtraction(state, "tum_fr1_rpy_dev", false); }
void BM_OrbExtractBonnCrowd(benchmark::State& state) { RunExtraction(state, "bonn_crowd_dev", false); }
void BM_OrbExtractBonnCrowdMasked70(benchmark::State& state) { RunExtraction(state, "bonn_crowd_dev", true); }

BENCHMARK(BM_OrbExtractTumRpy)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_OrbExtractBonnCrowd)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_OrbExtractBonnCrowdMasked70)->Unit(benchmark::kMillisecond);

}  // namespace

int main(int argc, char** argv) {
  cv::setNumThreads(1);  // one core: OpenCV's own worker threads would hide the cost
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
