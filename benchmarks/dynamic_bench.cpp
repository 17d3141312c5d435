// Per-frame cost of the dynamic stage (region growing, multi-view geometry check) and of
// rendering a synthetic frame. The *_Bonn* cases run on the real dev window
// (../shared/data/bonn_crowd_dev): ESPNetv2 person masks and Kinect depth. In a run, the same
// costs per frame are in OUT/timing.csv (grow_ms, geometry_ms).
//   build-*/benchmarks/dynamic_bench [--benchmark_filter=...]
#include <filesystem>

#include <benchmark/benchmark.h>
#include <opencv2/core/utility.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include "dynamic/geometry_check.h"
#include "dynamic/region_growing.h"
#include "feature/orb_extractor.h"
#include "io/trajectory_io.h"
#include "io/tum_sequence.h"
#include "semantic/class_groups.h"
#include "semantic/onnx_segmenter.h"
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

// Bonn crowd frames 40, 60, ..., 240 with ESPNetv2 (384x288) person masks, Bonn camera model
// and the ground-truth poses (nearest timestamp; marker poses, 1-2 cm from the camera).
struct BonnFrame {
  cv::Mat bgr, depth_m, person_mask, static_objects;
  Rigid3 world_from_cam;
};
struct BonnWindow {
  std::vector<BonnFrame> frames;
  PinholeCamera camera;
};

const BonnWindow* Bonn() {
  static const std::unique_ptr<BonnWindow> window = []() -> std::unique_ptr<BonnWindow> {
    const std::string dir = std::string(ESDSLAM_TEST_DATA_DIR) + "/data/bonn_crowd_dev";
    if (!std::filesystem::exists(dir)) return nullptr;
    auto out = std::make_unique<BonnWindow>();
    CameraIntrinsics k;
    k.fx = 542.822841, k.fy = 542.576870, k.cx = 315.593520, k.cy = 237.756098;
    k.k1 = 0.039903, k.k2 = -0.099343, k.p1 = -0.000730, k.p2 = -0.000144;
    out->camera = PinholeCamera(k);
    OnnxSegmenterOptions options;
    options.model_path = std::string(ESDSLAM_SOURCE_DIR) + "/models/espnetv2_s2.0_voc_384x288.onnx";
    options.input_width = 384, options.input_height = 288;
    OnnxSegmenter segmenter(options);
    const ClassGroups groups;
    const TumSequence sequence = TumSequence::Open(dir);
    const std::vector<StampedPose> truth = ReadTumTrajectory(sequence.groundtruth_path());
    for (std::size_t i = 40; i < sequence.frames().size(); i += 20) {
      const RgbdImages images = LoadRgbd(sequence.frames()[i], 5000.0);
      const SemanticMasks masks = groups.Masks(segmenter.Segment(images.bgr, 0.0).labels);
      const auto nearest = std::min_element(truth.begin(), truth.end(), [&](const auto& a, const auto& b) {
        return std::abs(a.timestamp - sequence.frames()[i].timestamp) < std::abs(b.timestamp - sequence.frames()[i].timestamp);
      });
      out->frames.push_back({images.bgr, images.depth_m, masks.dynamic, masks.static_objects, nearest->world_from_cam});
    }
    return out;
  }();
  return window.get();
}

// Region growing on ESPNetv2 person masks of real frames (people cover 10-60 % of the image).
void BM_RefineDynamicMask_BonnPersons(benchmark::State& state) {
  const BonnWindow* bonn = Bonn();
  if (bonn == nullptr) return state.SkipWithError("bonn_crowd_dev not found");
  std::size_t i = 0;
  double fraction = 0;
  for (auto _ : state) {
    const BonnFrame& frame = bonn->frames[i++ % bonn->frames.size()];
    benchmark::DoNotOptimize(RefineDynamicMask(frame.person_mask, frame.depth_m, RegionGrowingOptions{}).data);
  }
  for (const BonnFrame& frame : bonn->frames) fraction += cv::countNonZero(frame.person_mask) / (640.0 * 480 * bonn->frames.size());
  state.counters["person_fraction"] = fraction;
}
BENCHMARK(BM_RefineDynamicMask_BonnPersons)->Unit(benchmark::kMillisecond);

// The check of frame j against the 5 frames j-1 .. j-5 of the sampled window (20 frames apart,
// as keyframes), each with its 1000 ORB keypoints with depth off the person mask and its depth at
// half resolution; the current frame's person mask and static classes exempt, as in full mode.
void BM_GeometryCheck_Bonn(benchmark::State& state) {
  const BonnWindow* bonn = Bonn();
  if (bonn == nullptr) return state.SkipWithError("bonn_crowd_dev not found");
  const OrbExtractor extractor(OrbOptions{});
  std::vector<ReferenceKeyframe> references;
  for (const BonnFrame& frame : bonn->frames) {
    cv::Mat grey;
    cv::cvtColor(frame.bgr, grey, cv::COLOR_BGR2GRAY);
    std::vector<cv::KeyPoint> keypoints;
    cv::Mat descriptors;
    extractor.Extract(grey, frame.person_mask == 0, &keypoints, &descriptors);
    ReferenceKeyframe reference;
    reference.world_from_cam = frame.world_from_cam;
    for (const cv::KeyPoint& keypoint : keypoints) {
      const cv::Point p(cvRound(keypoint.pt.x), cvRound(keypoint.pt.y));
      const float z = frame.depth_m.at<float>(p);
      const cv::Point2f ideal = bonn->camera.Undistort({keypoint.pt})[0];
      if (z > 0) reference.points_world.push_back(frame.world_from_cam * bonn->camera.Backproject(Vec2(ideal.x, ideal.y), z));
    }
    cv::resize(frame.depth_m, reference.depth_m, cv::Size(), 0.5, 0.5, cv::INTER_NEAREST);
    reference.depth_scale = 0.5;
    references.push_back(std::move(reference));
  }
  std::size_t j = 5, flagged = 0, tested = 0, runs = 0;
  for (auto _ : state) {
    const BonnFrame& current = bonn->frames[j];
    const std::vector<ReferenceKeyframe> window(references.begin() + (j - 5), references.begin() + j);
    const cv::Mat exempt = current.person_mask | current.static_objects;
    const GeometryCheckResult result = CheckMultiViewGeometry(bonn->camera, current.world_from_cam.inverse(),
                                                              current.depth_m, window, GeometryCheckOptions{}, exempt);
    flagged += result.dynamic_points.size(), tested += result.num_tested, ++runs;
    j = j + 1 < bonn->frames.size() ? j + 1 : 5;
  }
  state.counters["tested"] = static_cast<double>(tested) / std::max<std::size_t>(1, runs);
  state.counters["flagged"] = static_cast<double>(flagged) / std::max<std::size_t>(1, runs);
}
BENCHMARK(BM_GeometryCheck_Bonn)->Unit(benchmark::kMillisecond);

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
