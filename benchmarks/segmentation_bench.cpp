// Segmentation time per frame (640x480 Bonn frame) for each shipped model, 1 and 2 OpenCV
// threads. Segment = resize + network + score upsampling + argmax + person probability;
// Network = Scores() only.
#include <filesystem>
#include <memory>
#include <string>

#include <benchmark/benchmark.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "semantic/onnx_segmenter.h"

namespace {

const char* kModels[] = {"espnetv2_s2.0_voc_256x192.onnx", "espnetv2_s2.0_voc_384x288.onnx",
                         "espnetv2_s2.0_voc_384x384.onnx"};
const int kSizes[][2] = {{256, 192}, {384, 288}, {384, 384}};

cv::Mat Frame() {
  const std::string path =
      std::string(ESDSLAM_TEST_DATA_DIR) + "/models/espnetv2/reference/bonn_crowd_1548339830.60015.png";
  cv::Mat bgr = cv::imread(path, cv::IMREAD_COLOR);
  if (bgr.empty()) {  // synthetic stand-in when ../shared is absent
    bgr = cv::Mat(480, 640, CV_8UC3);
    cv::randu(bgr, 0, 255);
  }
  return bgr;
}

std::unique_ptr<esdslam::OnnxSegmenter> MakeSegmenter(int model, int threads) {
  esdslam::OnnxSegmenterOptions options;
  options.model_path = std::string(ESDSLAM_SOURCE_DIR) + "/models/" + kModels[model];
  options.input_width = kSizes[model][0];
  options.input_height = kSizes[model][1];
  options.threads = threads;
  return std::make_unique<esdslam::OnnxSegmenter>(options);
}

void BM_Segment(benchmark::State& state) {
  const auto segmenter = MakeSegmenter(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  const cv::Mat bgr = Frame();
  for (auto _ : state) benchmark::DoNotOptimize(segmenter->Segment(bgr, 0.0).labels.data);
  state.SetLabel(kModels[state.range(0)]);
}

void BM_Network(benchmark::State& state) {
  const auto segmenter = MakeSegmenter(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  const cv::Mat bgr = Frame();
  for (auto _ : state) benchmark::DoNotOptimize(segmenter->Scores(bgr).size());
  state.SetLabel(kModels[state.range(0)]);
}

// Args: {model index, threads}
BENCHMARK(BM_Segment)->ArgsProduct({{0, 1, 2}, {1, 2}})->Unit(benchmark::kMillisecond)->MinTime(2.0)->UseRealTime();
BENCHMARK(BM_Network)->ArgsProduct({{0, 1}, {1, 2}})->Unit(benchmark::kMillisecond)->MinTime(2.0)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
