#include "optim/bundle_adjustment.h"

#include <algorithm>
#include <cstring>
#include <random>
#include <thread>

#include <gtest/gtest.h>

#include "common/error.h"
#include "optim/optim_test_scene.h"
#include "optim/reprojection_cost.h"

namespace esdslam {
namespace {

using test::kBf;

struct BaScene {
  BaProblem truth;    // exact poses and points
  BaProblem problem;  // noisy observations, perturbed estimates
  std::vector<bool> is_outlier;
};

// Keyframes on a 1 m arc looking at points 2-6 m away; every point is observed by the
// keyframes that see it (pixel noise noise_scale * 0.5 px * 1.2^level; half of them with depth).
// The first `fixed` keyframes stay at the truth; the others are perturbed by 3 cm / 1.5 deg,
// points by 5 cm (isotropic). `outlier_fraction` of the observations are wrong matches.
BaScene MakeScene(const PinholeCamera& camera, int keyframes, int points, int fixed, double outlier_fraction,
                  unsigned seed, double noise_scale = 1.0) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0, 1);
  std::normal_distribution<double> normal(0, 1);
  BaScene scene;
  for (int i = 0; i < keyframes; ++i) {
    const double s = keyframes > 1 ? static_cast<double>(i) / (keyframes - 1) - 0.5 : 0;
    const Rigid3 world_from_cam(ExpSO3(Vec3(0.05 * s, -0.3 * s, 0.02)), Vec3(1.0 * s, 0.1 * s * s, 0.2 * s));
    scene.truth.keyframes.push_back({world_from_cam.inverse(), i < fixed});
  }
  for (int j = 0; j < points; ++j) {
    const Vec3 p(-2.5 + 5 * unit(rng), -1.5 + 3 * unit(rng), 2 + 4 * unit(rng));
    scene.truth.points.push_back({p, false});
  }
  for (int j = 0; j < points; ++j) {
    for (int i = 0; i < keyframes; ++i) {
      const Vec3 p_cam = scene.truth.keyframes[i].cam_from_world * scene.truth.points[j].position_world;
      const Vec2 uv = camera.Project(p_cam);
      if (p_cam.z() < 0.1 || !camera.InImage(uv)) continue;
      const test::KeypointNoise noise = test::RandomLevel(&rng);
      BaObservation o;
      o.keyframe = i;
      o.point = j;
      o.information = noise.information;
      const bool stereo = unit(rng) < 0.5, outlier = unit(rng) < outlier_fraction;
      const double angle = 2 * M_PI * unit(rng), offset = 30 + 50 * unit(rng);
      o.pixel = outlier ? Vec2(uv + offset * Vec2(std::cos(angle), std::sin(angle)))
                        : Vec2(uv + noise_scale * noise.sigma * Vec2(normal(rng), normal(rng)));
      if (stereo) o.right_u = o.pixel.x() - kBf / p_cam.z() + (outlier ? 0.0 : noise_scale * noise.sigma * normal(rng));
      scene.truth.observations.push_back(o);
      scene.is_outlier.push_back(outlier);
    }
  }
  scene.problem = scene.truth;
  for (int i = fixed; i < keyframes; ++i) {
    BaKeyframe& kf = scene.problem.keyframes[i];
    kf.cam_from_world = test::RandomPerturbation(0.03, 1.5, &rng) * kf.cam_from_world;
  }
  for (BaPoint& point : scene.problem.points)
    point.position_world += 0.05 / std::sqrt(3.0) * Vec3(normal(rng), normal(rng), normal(rng));
  return scene;
}

// RMS of the unweighted reprojection error (left image) over the true inliers.
double ReprojectionRms(const PinholeCamera& camera, const BaProblem& problem, const std::vector<bool>& is_outlier) {
  double sum = 0;
  int count = 0;
  for (size_t k = 0; k < problem.observations.size(); ++k) {
    if (is_outlier[k]) continue;
    const BaObservation& o = problem.observations[k];
    const Vec3 p_cam = problem.keyframes[o.keyframe].cam_from_world * problem.points[o.point].position_world;
    sum += (camera.Project(p_cam) - o.pixel).squaredNorm();
    ++count;
  }
  return std::sqrt(sum / count);
}

bool BitwiseEqual(const Rigid3& a, const Rigid3& b) {
  return std::memcmp(a.rotation().coeffs().data(), b.rotation().coeffs().data(), 4 * sizeof(double)) == 0 &&
         std::memcmp(a.translation().data(), b.translation().data(), 3 * sizeof(double)) == 0;
}

// Low noise (0.05 px): the estimate must land on the truth, up to that noise.
TEST(BundleAdjust, RecoversTheTruthWithTwoFixedKeyframes) {
  const PinholeCamera camera = test::TumLikeCamera();
  BaScene scene = MakeScene(camera, 6, 300, 2, 0.0, 1, /*noise_scale=*/0.1);
  const BaProblem before = scene.problem;
  const double rms_before = ReprojectionRms(camera, scene.problem, scene.is_outlier);
  const BaSummary summary = BundleAdjust(camera, kBf, BundleAdjustmentOptions{}, &scene.problem);
  EXPECT_GT(rms_before, 5.0);
  EXPECT_LT(ReprojectionRms(camera, scene.problem, scene.is_outlier), 0.1);
  EXPECT_LT(summary.final_cost, 1e-3 * summary.initial_cost);
  EXPECT_FALSE(summary.aborted);
  EXPECT_EQ(summary.outliers, 0);
  for (int i = 0; i < 6; ++i) {
    const Rigid3& estimate = scene.problem.keyframes[i].cam_from_world;
    if (i < 2) {
      EXPECT_TRUE(BitwiseEqual(estimate, before.keyframes[i].cam_from_world)) << i;
    } else {
      EXPECT_LT(test::CentreError(estimate, scene.truth.keyframes[i].cam_from_world), 0.002) << i;
      EXPECT_LT(test::RotationErrorDeg(estimate, scene.truth.keyframes[i].cam_from_world), 0.02) << i;
    }
  }
  std::vector<double> point_errors;
  for (size_t j = 0; j < scene.problem.points.size(); ++j)
    point_errors.push_back((scene.problem.points[j].position_world - scene.truth.points[j].position_world).norm());
  std::nth_element(point_errors.begin(), point_errors.begin() + point_errors.size() / 2, point_errors.end());
  EXPECT_LT(point_errors[point_errors.size() / 2], 0.005);  // started at ~5 cm
}

// Realistic noise (0.5 px * 1.2^level): the truth is no longer the optimum, but the result must
// fit the observations at least as well as the truth does (a converged maximum likelihood fit).
TEST(BundleAdjust, FitsAtLeastAsWellAsTheTruthUnderRealisticNoise) {
  const PinholeCamera camera = test::TumLikeCamera();
  BaScene scene = MakeScene(camera, 6, 300, 2, 0.0, 7);
  const BaSummary summary = BundleAdjust(camera, kBf, BundleAdjustmentOptions{}, &scene.problem);
  const StereoIntrinsics k(camera, kBf);
  double truth_cost = 0;
  for (const BaObservation& o : scene.problem.observations) {
    if (o.outlier) continue;
    bool in_front = false;
    truth_cost += 0.5 * ReprojectionChi2(k, {o.pixel, o.right_u, std::sqrt(o.information)},
                                         scene.truth.keyframes[o.keyframe].cam_from_world,
                                         scene.truth.points[o.point].position_world, &in_front);
  }
  EXPECT_LE(summary.final_cost, truth_cost);
  EXPECT_GT(summary.final_cost, 0.5 * truth_cost);
  for (int i = 2; i < 6; ++i) {
    EXPECT_LT(test::CentreError(scene.problem.keyframes[i].cam_from_world, scene.truth.keyframes[i].cam_from_world),
              0.015);
  }
}

TEST(BundleAdjust, FlagsGrossOutliersAndStillConverges) {
  const PinholeCamera camera = test::TumLikeCamera();
  BaScene scene = MakeScene(camera, 8, 300, 2, 0.1, 2);
  BundleAdjust(camera, kBf, BundleAdjustmentOptions{}, &scene.problem);
  int true_outliers = 0, caught = 0, flagged = 0;
  for (size_t k = 0; k < scene.is_outlier.size(); ++k) {
    true_outliers += scene.is_outlier[k];
    flagged += scene.problem.observations[k].outlier;
    caught += scene.is_outlier[k] && scene.problem.observations[k].outlier;
  }
  ASSERT_GT(true_outliers, 50);
  EXPECT_GT(static_cast<double>(caught) / true_outliers, 0.95);
  EXPECT_GT(static_cast<double>(caught) / flagged, 0.95);
  // Same accuracy as without outliers (noise-limited, see FitsAtLeastAsWellAsTheTruth...).
  for (int i = 2; i < 8; ++i)
    EXPECT_LT(test::CentreError(scene.problem.keyframes[i].cam_from_world, scene.truth.keyframes[i].cam_from_world),
              0.015);
}

TEST(BundleAdjust, KeepsFixedPointsAndKeyframesBitwiseAndLowersErrorWithOneFixed) {
  const PinholeCamera camera = test::TumLikeCamera();
  BaScene scene = MakeScene(camera, 5, 200, 1, 0.0, 3);
  for (int j = 0; j < 20; ++j) scene.problem.points[j].fixed = true;
  const BaProblem before = scene.problem;
  const double rms_before = ReprojectionRms(camera, scene.problem, scene.is_outlier);
  BundleAdjust(camera, kBf, BundleAdjustmentOptions{}, &scene.problem);
  EXPECT_LT(ReprojectionRms(camera, scene.problem, scene.is_outlier), 0.2 * rms_before);
  EXPECT_TRUE(BitwiseEqual(scene.problem.keyframes[0].cam_from_world, before.keyframes[0].cam_from_world));
  for (int j = 0; j < 20; ++j)
    EXPECT_EQ(std::memcmp(scene.problem.points[j].position_world.data(), before.points[j].position_world.data(),
                          3 * sizeof(double)),
              0);
}

TEST(BundleAdjust, StopFlagSetBeforehandAbortsWithoutChanges) {
  const PinholeCamera camera = test::TumLikeCamera();
  BaScene scene = MakeScene(camera, 4, 100, 1, 0.0, 4);
  const BaProblem before = scene.problem;
  const std::atomic<bool> stop(true);
  const BaSummary summary = BundleAdjust(camera, kBf, BundleAdjustmentOptions{}, &scene.problem, &stop);
  EXPECT_TRUE(summary.aborted);
  for (int i = 0; i < 4; ++i)
    EXPECT_TRUE(BitwiseEqual(scene.problem.keyframes[i].cam_from_world, before.keyframes[i].cam_from_world));
}

TEST(BundleAdjust, StopFlagSetByAnotherThreadAbortsEarlyWithAConsistentState) {
  const PinholeCamera camera = test::TumLikeCamera();
  BaScene scene = MakeScene(camera, 10, 1500, 2, 0.0, 8);
  const double rms_before = ReprojectionRms(camera, scene.problem, scene.is_outlier);
  std::atomic<bool> stop(false);
  // Set as soon as possible: the problem takes far longer to build than the thread to start.
  std::thread setter([&stop] { stop = true; });
  BundleAdjustmentOptions options;
  options.iterations_first = 50;
  const BaSummary summary = BundleAdjust(camera, kBf, options, &scene.problem, &stop);
  setter.join();
  EXPECT_TRUE(summary.aborted);
  EXPECT_LE(summary.final_cost, summary.initial_cost);
  EXPECT_LE(ReprojectionRms(camera, scene.problem, scene.is_outlier), rms_before);
}

TEST(BundleAdjust, IsDeterministic) {
  const PinholeCamera camera = test::TumLikeCamera();
  BaScene a = MakeScene(camera, 5, 150, 2, 0.05, 5);
  BaScene b = a;
  BundleAdjust(camera, kBf, BundleAdjustmentOptions{}, &a.problem);
  BundleAdjust(camera, kBf, BundleAdjustmentOptions{}, &b.problem);
  for (int i = 0; i < 5; ++i)
    EXPECT_TRUE(BitwiseEqual(a.problem.keyframes[i].cam_from_world, b.problem.keyframes[i].cam_from_world));
  for (size_t k = 0; k < a.problem.observations.size(); ++k)
    EXPECT_EQ(a.problem.observations[k].outlier, b.problem.observations[k].outlier);
}

TEST(BundleAdjust, EmptyProblemIsANoOp) {
  BaProblem problem;
  problem.keyframes.push_back({Rigid3(), false});
  const BaSummary summary = BundleAdjust(test::TumLikeCamera(), kBf, BundleAdjustmentOptions{}, &problem);
  EXPECT_EQ(summary.initial_cost, 0);
  EXPECT_EQ(summary.final_cost, 0);
  EXPECT_EQ(summary.outliers, 0);
  EXPECT_FALSE(summary.aborted);
}

TEST(BundleAdjust, RejectsBadIndices) {
  const PinholeCamera camera = test::TumLikeCamera();
  BaScene scene = MakeScene(camera, 3, 50, 1, 0.0, 6);
  scene.problem.observations[0].point = 50;
  EXPECT_THROW(BundleAdjust(camera, kBf, BundleAdjustmentOptions{}, &scene.problem), Error);
  scene.problem.observations[0].point = 0;
  scene.problem.observations[0].keyframe = -1;
  EXPECT_THROW(BundleAdjust(camera, kBf, BundleAdjustmentOptions{}, &scene.problem), Error);
  BundleAdjustmentOptions options;
  options.num_threads = 0;
  EXPECT_THROW(options.Check(), Error);
}

}  // namespace
}  // namespace esdslam
