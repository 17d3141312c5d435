// Motion-only BA and local BA timings on synthetic scenes of typical size.
//   build-<you>/benchmarks/optim_bench
#include <cmath>
#include <random>

#include <benchmark/benchmark.h>

#include "optim/bundle_adjustment.h"
#include "optim/pose_optimizer.h"

namespace esdslam {
namespace {

constexpr double kBf = 40.0;

PinholeCamera BenchCamera() {
  CameraIntrinsics intrinsics;
  intrinsics.fx = 517.3;
  intrinsics.fy = 516.5;
  intrinsics.cx = 318.6;
  intrinsics.cy = 255.3;
  return PinholeCamera(intrinsics);
}

Rigid3 Perturbation(double translation, double rotation_rad, std::mt19937* rng) {
  std::normal_distribution<double> normal(0, 1);
  const Vec3 t(normal(*rng), normal(*rng), normal(*rng)), axis(normal(*rng), normal(*rng), normal(*rng));
  return Rigid3(ExpSO3(axis.normalized() * rotation_rad), t.normalized() * translation);
}

// `count` observations (70% with depth, 20% wrong matches, 0.5 px * 1.2^level noise).
std::vector<PoseObservation> PoseScene(const PinholeCamera& camera, const Rigid3& cam_from_world, int count) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(0, 640), v(0, 480), z(0.8, 6), unit(0, 1);
  std::normal_distribution<double> normal(0, 1);
  const Rigid3 world_from_cam = cam_from_world.inverse();
  std::vector<PoseObservation> observations(count);
  for (PoseObservation& o : observations) {
    const Vec2 pixel(u(rng), v(rng));
    const double depth = z(rng), scale = std::pow(1.2, static_cast<int>(unit(rng) * 4));
    o.point_world = world_from_cam * camera.Backproject(pixel, depth);
    o.information = 1 / (scale * scale);
    const bool outlier = unit(rng) < 0.2;
    o.pixel = outlier ? Vec2(u(rng), v(rng)) : Vec2(pixel + 0.5 * scale * Vec2(normal(rng), normal(rng)));
    if (unit(rng) < 0.7) o.right_u = o.pixel.x() - kBf / (outlier ? z(rng) : depth);
  }
  return observations;
}

void BM_OptimizePose(benchmark::State& state) {
  const PinholeCamera camera = BenchCamera();
  const Rigid3 truth(ExpSO3(Vec3(0.3, -0.5, 0.2)), Vec3(0.4, -0.2, 1.1));
  const std::vector<PoseObservation> scene = PoseScene(camera, truth, static_cast<int>(state.range(0)));
  std::mt19937 rng(2);
  const Rigid3 start = Perturbation(0.03, 0.03, &rng) * truth;
  int inliers = 0;
  for (auto _ : state) {
    std::vector<PoseObservation> observations = scene;
    Rigid3 pose = start;
    inliers = OptimizePose(camera, kBf, PoseOptimizerOptions{}, &observations, &pose);
    benchmark::DoNotOptimize(pose);
  }
  state.counters["inliers"] = inliers;
}
BENCHMARK(BM_OptimizePose)->Arg(300)->Arg(600)->Unit(benchmark::kMillisecond);

// A local BA window: `keyframes` keyframes along a 2 m path (the first 2 fixed, as ORB-SLAM2's
// keyframes that see local points but are not covisible), `points` points 2-6 m ahead.
BaProblem BaScene(const PinholeCamera& camera, int keyframes, int points) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> unit(0, 1);
  std::normal_distribution<double> normal(0, 1);
  BaProblem problem, truth;
  for (int i = 0; i < keyframes; ++i) {
    const double s = static_cast<double>(i) / (keyframes - 1) - 0.5;
    truth.keyframes.push_back({Rigid3(ExpSO3(Vec3(0, -0.3 * s, 0)), Vec3(2 * s, 0, 0)).inverse(), i < 2});
  }
  for (int j = 0; j < points; ++j)
    truth.points.push_back({Vec3(-3 + 6 * unit(rng), -1.5 + 3 * unit(rng), 2 + 4 * unit(rng)), false});
  for (int j = 0; j < points; ++j) {
    for (int i = 0; i < keyframes; ++i) {
      const Vec3 p = truth.keyframes[i].cam_from_world * truth.points[j].position_world;
      const Vec2 uv = camera.Project(p);
      if (p.z() < 0.1 || !camera.InImage(uv) || unit(rng) < 0.4) continue;  // 60% matched
      BaObservation o;
      o.keyframe = i;
      o.point = j;
      o.pixel = uv + 0.5 * Vec2(normal(rng), normal(rng));
      if (unit(rng) < 0.6) o.right_u = o.pixel.x() - kBf / p.z();
      truth.observations.push_back(o);
    }
  }
  problem = truth;
  for (int i = 2; i < keyframes; ++i)
    problem.keyframes[i].cam_from_world = Perturbation(0.02, 0.01, &rng) * problem.keyframes[i].cam_from_world;
  for (BaPoint& point : problem.points) point.position_world += 0.03 * Vec3(normal(rng), normal(rng), normal(rng));
  return problem;
}

void BM_LocalBundleAdjustment(benchmark::State& state) {
  const PinholeCamera camera = BenchCamera();
  const BaProblem scene = BaScene(camera, static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  BundleAdjustmentOptions options;
  options.num_threads = 1;
  for (auto _ : state) {
    BaProblem problem = scene;
    const BaSummary summary = BundleAdjust(camera, kBf, options, &problem);
    benchmark::DoNotOptimize(summary);
  }
  state.counters["observations"] = static_cast<double>(scene.observations.size());
}
BENCHMARK(BM_LocalBundleAdjustment)->Args({10, 2000})->Args({20, 4000})->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace esdslam

BENCHMARK_MAIN();
