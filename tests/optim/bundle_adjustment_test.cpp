#include "optim/bundle_adjustment.h"

#include <algorithm>
#include <cstring>
#include <random>
#include <thread>

#include <gtest/gtest.h>

#include "common/error.h"
#include "optim/ba_test_scene.h"
#include "optim/optim_test_scene.h"
#include "optim/reprojection_cost.h"

namespace esdslam {
namespace {

using test::BaScene;
using test::kBf;
using test::MakeScene;
using test::ReprojectionRms;

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

// The fixed-block solver (windows up to max_dense_keyframes) and Ceres (above it) minimise the
// same cost: on the same window they must agree on the cost, the outliers and the poses (to
// 0.2 mm / 0.005 deg against 3 cm / 1.5 deg of perturbation: both stop at the same relative
// cost tolerance, 1e-6, so they part along the window's weakest direction by that much).
TEST(BundleAdjust, OwnSchurSolverAgreesWithCeres) {
  const PinholeCamera camera = test::TumLikeCamera();
  for (const unsigned seed : {11u, 12u, 13u}) {
    BaScene own = MakeScene(camera, 8, 400, 2, 0.05, seed);
    BaScene ceres = own;
    BundleAdjustmentOptions ceres_options;
    ceres_options.max_dense_keyframes = 0;
    const BaSummary own_summary = BundleAdjust(camera, kBf, BundleAdjustmentOptions{}, &own.problem);
    const BaSummary ceres_summary = BundleAdjust(camera, kBf, ceres_options, &ceres.problem);
    EXPECT_NEAR(own_summary.initial_cost, ceres_summary.initial_cost, 1e-9 * ceres_summary.initial_cost) << seed;
    EXPECT_NEAR(own_summary.final_cost, ceres_summary.final_cost, 1e-4 * ceres_summary.final_cost) << seed;
    EXPECT_LT(own_summary.final_cost, 0.05 * own_summary.initial_cost) << seed;
    EXPECT_EQ(own_summary.outliers, ceres_summary.outliers) << seed;
    for (int i = 2; i < 8; ++i) {
      const Rigid3& a = own.problem.keyframes[i].cam_from_world;
      const Rigid3& b = ceres.problem.keyframes[i].cam_from_world;
      EXPECT_LT(test::CentreError(a, b), 2e-4) << seed << " keyframe " << i;
      EXPECT_LT(test::RotationErrorDeg(a, b), 5e-3) << seed << " keyframe " << i;
    }
  }
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
  options = BundleAdjustmentOptions{};
  options.max_dense_keyframes = -1;
  EXPECT_THROW(options.Check(), Error);
}

}  // namespace
}  // namespace esdslam
