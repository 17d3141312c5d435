// Loop-closing costs: geometric verification of one candidate (rendered views of the synthetic
// room, the shipped vocabulary), pose-graph optimisation over an essential graph of 100
// keyframes, and the global bundle adjustment of a 40-keyframe / 4000-point map. Timings of the
// whole pipeline on a run are in the `esdslam run` summary (docs/RESULTS.md).
#include <random>

#include <benchmark/benchmark.h>
#include <opencv2/imgproc.hpp>

#include "feature/orb_extractor.h"
#include "loop/loop_verification.h"
#include "loop/pose_graph.h"
#include "map/map.h"
#include "optim/bundle_adjustment.h"
#include "synth/synthetic_scene.h"

namespace esdslam {
namespace {

const std::string kShippedVocabulary = std::string(ESDSLAM_SOURCE_DIR) + "/models/vocabulary/orb_vocabulary.bin";

// Two keyframes of the synthetic room 12 frames apart, the second in a drifted map frame, each
// with a map point per keypoint with depth.
struct TwoKeyFrames {
  SyntheticScene scene{SynthPreset("static")};
  OrbExtractor extractor{OrbOptions{}};
  std::shared_ptr<RgbdRig> rig = std::make_shared<RgbdRig>();
  Map map;
  KeyFrame* loop = nullptr;
  KeyFrame* current = nullptr;

  TwoKeyFrames() {
    rig->camera = scene.camera();
    rig->bf = 40.0;
    rig->th_depth_m = 3.0;
    rig->pyramid.num_levels = extractor.num_levels();
    rig->pyramid.log_scale_factor = std::log(1.2);
    rig->pyramid.scale_factors = extractor.scale_factors();
    rig->pyramid.level_sigma2 = extractor.level_sigma2();
    rig->pyramid.inv_level_sigma2 = extractor.inv_level_sigma2();
    loop = Add(scene.WorldFromCam(0), Rigid3());
    current = Add(scene.WorldFromCam(12), Rigid3(ExpSO3(Vec3(0, 0, 0.05)), Vec3(0.15, -0.08, 0.03)));
  }

  KeyFrame* Add(const Rigid3& world_from_cam, const Rigid3& map_from_world) {
    const SynthFrame frame = scene.Render(world_from_cam, 0.0, 1);
    auto features = std::make_shared<FeatureSet>();
    features->rig = rig;
    cv::Mat gray;
    cv::cvtColor(frame.bgr, gray, cv::COLOR_BGR2GRAY);
    extractor.Extract(gray, cv::Mat(), &features->keypoints, &features->descriptors);
    std::vector<int> levels;
    for (const cv::KeyPoint& keypoint : features->keypoints) {
      features->undistorted.push_back(keypoint.pt);
      const float z = frame.depth_m.at<float>(cvRound(keypoint.pt.y), cvRound(keypoint.pt.x));
      features->depth.push_back(z);
      features->right_u.push_back(z > 0 ? keypoint.pt.x - static_cast<float>(rig->bf / z) : -1.f);
      features->is_dynamic.push_back(0);
      levels.push_back(keypoint.octave);
    }
    const PinholeCamera& camera = rig->camera;
    features->grid = std::make_unique<FeatureGrid>(features->undistorted, levels, camera.min_u(), camera.max_u(),
                                                   camera.min_v(), camera.max_v());
    const Rigid3 map_from_cam = map_from_world * world_from_cam;
    KeyFrame* keyframe = map.CreateKeyFrame(0, 0, features, map_from_cam.inverse());
    map.AddKeyFrame(keyframe);
    for (int i = 0; i < features->size(); ++i) {
      if (!features->has_depth(i)) continue;
      MapPoint* point = map.CreateMapPoint(map_from_cam * features->BackprojectCam(i), keyframe);
      point->AddObservation(keyframe, i, true);
      keyframe->AddMapPoint(point, i);
      point->ComputeDistinctiveDescriptor();
      point->UpdateNormalAndDepth();
      map.AddMapPoint(point);
    }
    return keyframe;
  }
};

void BM_LoopCandidateVerification(benchmark::State& state) {
  TwoKeyFrames scene;
  PlaceRecognition places(std::make_shared<const Vocabulary>(Vocabulary::Load(kShippedVocabulary)));
  places.AddKeyFrame(scene.loop);
  places.AddKeyFrame(scene.current);
  LoopMatch match;
  int verified = 0;
  for (auto _ : state) verified += VerifyLoopCandidate(scene.current, scene.loop, places, {}, 1, &match);
  state.counters["verified"] = static_cast<double>(verified) / state.iterations();
  state.counters["inliers"] = match.refined_inliers;
  state.counters["matches"] = match.total_matches;
}
BENCHMARK(BM_LoopCandidateVerification)->Unit(benchmark::kMillisecond);

// 100 keyframes on a circle: odometry chain with drift, covisibility edges to the next 3, one
// loop edge, the first fixed.
void BM_EssentialGraphOptimization(benchmark::State& state) {
  const int n = 100;
  std::map<long, Rigid3> truth, drifted;
  const Rigid3 bias(ExpSO3(Vec3(0, 0.002, 0)), Vec3(0.003, 0, 0));
  for (long i = 0; i < n; ++i) {
    const double angle = 2 * M_PI * i / n;
    truth[i] = Rigid3(ExpSO3(Vec3(0, -angle, 0)), Vec3(2 * std::sin(angle), 0, 2 * std::cos(angle))).inverse();
    drifted[i] = i == 0 ? truth[0] : bias * truth[i] * truth[i - 1].inverse() * drifted[i - 1];
  }
  std::vector<PoseGraphEdge> edges;
  for (long i = 1; i < n; ++i)
    for (long j = std::max(0L, i - 3); j < i; ++j) edges.push_back(RelativePoseEdge(i, j, drifted[i], drifted[j]));
  edges.push_back(RelativePoseEdge(n - 1, 0, truth[n - 1], truth[0]));
  for (auto _ : state) benchmark::DoNotOptimize(OptimizePoseGraph(drifted, edges, {0}).final_cost);
  state.counters["edges"] = static_cast<double>(edges.size());
}
BENCHMARK(BM_EssentialGraphOptimization)->Unit(benchmark::kMillisecond);

// 40 keyframes along a line, 4000 points seen by the 5 nearest keyframes with depth, noisy start.
void BM_GlobalBundleAdjustment(benchmark::State& state) {
  const PinholeCamera camera(SynthOptions::DefaultIntrinsics());
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 1.0);
  BaProblem truth;
  for (int k = 0; k < 40; ++k) truth.keyframes.push_back({Rigid3(Quat::Identity(), Vec3(-0.1 * k, 0, 0)), k == 0});
  std::uniform_real_distribution<double> x(-1.0, 5.0), y(-1.0, 1.0), z(2.0, 4.0);
  for (int p = 0; p < 4000; ++p) truth.points.push_back({Vec3(x(rng), y(rng), z(rng)), false});
  for (int p = 0; p < 4000; ++p) {
    const int nearest = std::clamp(static_cast<int>(truth.points[p].position_world.x() / 0.1), 0, 39);
    for (int k = std::max(0, nearest - 2); k <= std::min(39, nearest + 2); ++k) {
      const Vec3 c = truth.keyframes[k].cam_from_world * truth.points[p].position_world;
      BaObservation o;
      o.keyframe = k, o.point = p;
      o.pixel = camera.Project(c) + 0.5 * Vec2(noise(rng), noise(rng));
      o.right_u = o.pixel.x() - 40.0 / c.z();
      truth.observations.push_back(o);
    }
  }
  BundleAdjustmentOptions options;
  options.iterations_first = 10;  // as the global BA after a loop
  options.iterations_second = 0;
  for (auto _ : state) {
    state.PauseTiming();
    BaProblem problem = truth;
    for (std::size_t k = 1; k < problem.keyframes.size(); ++k)
      problem.keyframes[k].cam_from_world = Rigid3(Quat::Identity(), Vec3(0.01 * noise(rng), 0, 0)) * problem.keyframes[k].cam_from_world;
    state.ResumeTiming();
    benchmark::DoNotOptimize(BundleAdjust(camera, 40.0, options, &problem).final_cost);
  }
  state.counters["observations"] = static_cast<double>(truth.observations.size());
}
BENCHMARK(BM_GlobalBundleAdjustment)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace esdslam

BENCHMARK_MAIN();
