// Per-frame cost of the dynamic stage (region growing, multi-view geometry check) and of
// rendering a synthetic frame.
//   build-*/benchmarks/dynamic_bench [--benchmark_filter=...]
#include <filesystem>

#include <benchmark/benchmark.h>
#include <opencv2/core/utility.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include "dynamic/geometry_check.h"
#include "dynamic/region_growing.h"
#include "io/tum_sequence.h"
#include "synth/synthetic_scene.h"

namespace esdslam {
namespace {

const SyntheticScene& Scene() {
  static const SyntheticScene scene([] {
    SynthOptions options = SynthPreset("dynamic");
    options.num_frames = 60;
    return options;
  }());
  return scene;
}

cv::Mat Dilated(const cv::Mat& mask, int radius) {
  cv::Mat out;
  cv::dilate(mask, out, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * radius + 1, 2 * radius + 1)));
  return out;
}

// Region growing on a 640x480 synthetic frame with 2 people covering ~30 % of the image; the
// coarse mask is the ground truth dilated by 10 px.
void BM_RefineDynamicMask_Synthetic(benchmark::State& state) {
  const SynthFrame frame = Scene().RenderFrame(40);
  const cv::Mat raw = Dilated(frame.mover_mask != 0, 10);
  for (auto _ : state) benchmark::DoNotOptimize(RefineDynamicMask(raw, frame.depth_m, RegionGrowingOptions{}));
  state.counters["mask_fraction"] = static_cast<double>(cv::countNonZero(raw)) / raw.total();
}
BENCHMARK(BM_RefineDynamicMask_Synthetic)->Unit(benchmark::kMillisecond);

ReferenceKeyframe MakeKeyframe(const SynthFrame& frame) {
  cv::Mat grey;
  cv::cvtColor(frame.bgr, grey, cv::COLOR_BGR2GRAY);
  std::vector<cv::KeyPoint> corners;
  cv::FAST(grey, corners, 20, true);
  cv::KeyPointsFilter::retainBest(corners, 1000);
  ReferenceKeyframe keyframe;
  keyframe.world_from_cam = frame.world_from_cam;
  for (const auto& kp : corners) {
    const cv::Point p(cvRound(kp.pt.x), cvRound(kp.pt.y));
    const float z = frame.depth_m.at<float>(p);
    if (z > 0) keyframe.points_world.push_back(frame.world_from_cam * Scene().camera().Backproject(Vec2(p.x, p.y), z));
  }
  keyframe.depth_m = frame.depth_m;
  return keyframe;
}

// Geometry check of a 640x480 frame against 5 keyframes of ~1000 points each (with depth).
void BM_GeometryCheck_Synthetic(benchmark::State& state) {
  const SynthFrame current = Scene().RenderFrame(45);
  std::vector<ReferenceKeyframe> keyframes;
  for (const int index : {15, 21, 27, 33, 39}) keyframes.push_back(MakeKeyframe(Scene().RenderFrame(index)));
  std::size_t flagged = 0;
  for (auto _ : state) {
    const GeometryCheckResult result = CheckMultiViewGeometry(Scene().camera(), current.world_from_cam.inverse(),
                                                              current.depth_m, keyframes, GeometryCheckOptions{});
    flagged = result.dynamic_points.size();
  }
  state.counters["flagged"] = static_cast<double>(flagged);
}
BENCHMARK(BM_GeometryCheck_Synthetic)->Unit(benchmark::kMillisecond);

// Region growing on real Kinect depth (Bonn crowd): there are no person masks, so the mask is a
// person-sized block (200 x 400 px) in the image centre; this times the growth on real depth
// noise and holes, not its accuracy.
void BM_RefineDynamicMask_BonnDepth(benchmark::State& state) {
  const std::string dir = std::string(ESDSLAM_TEST_DATA_DIR) + "/data/bonn_crowd_dev";
  if (!std::filesystem::exists(dir)) {
    state.SkipWithError("bonn_crowd_dev not found");
    return;
  }
  const TumSequence sequence = TumSequence::Open(dir);
  std::vector<cv::Mat> depths;
  for (std::size_t i = 60; i < sequence.frames().size() && depths.size() < 10; i += 10)
    depths.push_back(LoadRgbd(sequence.frames()[i], 5000.0).depth_m);
  cv::Mat raw = cv::Mat::zeros(depths[0].size(), CV_8U);
  raw(cv::Rect(220, 40, 200, 400)).setTo(255);
  std::size_t i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(RefineDynamicMask(raw, depths[i++ % depths.size()], RegionGrowingOptions{}));
}
BENCHMARK(BM_RefineDynamicMask_BonnDepth)->Unit(benchmark::kMillisecond);

// Rendering one 640x480 frame (2x2 supersampling, 3 movers) on one core.
void BM_SynthRenderFrame_OneCore(benchmark::State& state) {
  const int threads = cv::getNumThreads();
  cv::setNumThreads(1);
  int index = 0;
  for (auto _ : state) benchmark::DoNotOptimize(Scene().RenderFrame(index++ % 60));
  cv::setNumThreads(threads);
}
BENCHMARK(BM_SynthRenderFrame_OneCore)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace esdslam

BENCHMARK_MAIN();
