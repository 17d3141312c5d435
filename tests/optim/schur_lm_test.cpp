#include "optim/schur_lm.h"

#include <atomic>
#include <cstring>

#include <gtest/gtest.h>

#include "optim/ba_test_scene.h"
#include "optim/optim_test_scene.h"

namespace esdslam {
namespace {

using test::kBf;

BaState StateOf(const BaProblem& problem) {
  BaState state;
  state.poses.resize(problem.keyframes.size());
  for (size_t i = 0; i < problem.keyframes.size(); ++i)
    PoseToBlock(problem.keyframes[i].cam_from_world, state.poses[i].data());
  for (const BaPoint& point : problem.points) state.points.push_back(point.position_world);
  return state;
}

bool SameBits(const BaState& a, const BaState& b) {
  return std::memcmp(a.poses.data(), b.poses.data(), a.poses.size() * sizeof(a.poses[0])) == 0 &&
         std::memcmp(a.points.data(), b.points.data(), a.points.size() * sizeof(Vec3)) == 0;
}

// Points held fixed at the truth: only poses move (no Schur elimination), and they reach the truth.
TEST(SolveSchurLm, PosesAloneReachTheTruthWhenPointsAreFixed) {
  const PinholeCamera camera = test::TumLikeCamera();
  test::BaScene scene = test::MakeScene(camera, 5, 200, 1, 0.0, 21, /*noise_scale=*/0.05);
  for (size_t j = 0; j < scene.problem.points.size(); ++j) scene.problem.points[j] = {scene.truth.points[j].position_world, true};
  BaState state = StateOf(scene.problem);
  const StereoIntrinsics k(camera, kBf);
  const SchurLmSummary summary = SolveSchurLm(k, scene.problem, SchurLmOptions{}, nullptr, &state);
  EXPECT_LT(summary.final_cost, 1e-3 * summary.initial_cost);
  EXPECT_LE(summary.iterations, SchurLmOptions{}.max_iterations);
  for (int i = 1; i < 5; ++i) {
    EXPECT_LT(test::CentreError(PoseFromBlock(state.poses[i].data()), scene.truth.keyframes[i].cam_from_world), 1e-3);
  }
  EXPECT_EQ(std::memcmp(state.points.data(), StateOf(scene.problem).points.data(), state.points.size() * sizeof(Vec3)),
            0);
}

// All keyframes fixed at the truth: only points move (an empty reduced system), to the truth.
TEST(SolveSchurLm, PointsAloneReachTheTruthWhenKeyframesAreFixed) {
  const PinholeCamera camera = test::TumLikeCamera();
  test::BaScene scene = test::MakeScene(camera, 4, 150, 4, 0.0, 22, /*noise_scale=*/0.05);
  BaState state = StateOf(scene.problem);
  const SchurLmSummary summary = SolveSchurLm(StereoIntrinsics(camera, kBf), scene.problem, SchurLmOptions{}, nullptr, &state);
  EXPECT_LT(summary.final_cost, 1e-3 * summary.initial_cost);
  // Points with a depth reading are fully constrained by one view; mono-only ones may not be.
  // Depth noise grows as z^2: 0.025-0.04 px of disparity noise is up to 3 cm at 6 m, so the mean
  // error is checked against the 5 cm of the start, and the worst against the noise.
  std::vector<bool> has_depth(state.points.size(), false);
  for (const BaObservation& o : scene.problem.observations) has_depth[o.point] = has_depth[o.point] || o.right_u >= 0;
  double worst = 0, sum = 0;
  int checked = 0;
  for (size_t j = 0; j < state.points.size(); ++j) {
    if (!has_depth[j]) continue;
    const double error = (state.points[j] - scene.truth.points[j].position_world).norm();
    worst = std::max(worst, error);
    sum += error;
    ++checked;
  }
  ASSERT_GT(checked, 100);
  EXPECT_LT(sum / checked, 0.005);
  EXPECT_LT(worst, 0.04);
}

TEST(SolveSchurLm, RespectsTheIterationCapAndTheStopFlag) {
  const PinholeCamera camera = test::TumLikeCamera();
  const test::BaScene scene = test::MakeScene(camera, 6, 200, 2, 0.0, 23);
  const StereoIntrinsics k(camera, kBf);
  SchurLmOptions options;
  options.max_iterations = 1;
  BaState state = StateOf(scene.problem);
  const SchurLmSummary one = SolveSchurLm(k, scene.problem, options, nullptr, &state);
  EXPECT_EQ(one.iterations, 1);
  EXPECT_LT(one.final_cost, one.initial_cost);

  const std::atomic<bool> stop{true};
  BaState untouched = StateOf(scene.problem);
  const SchurLmSummary stopped = SolveSchurLm(k, scene.problem, SchurLmOptions{}, &stop, &untouched);
  EXPECT_TRUE(stopped.stopped);
  EXPECT_EQ(stopped.iterations, 0);
  EXPECT_TRUE(SameBits(untouched, StateOf(scene.problem)));
}

// With the robust loss, wrong matches (30-80 px off) are down-weighted: the fit on the inliers is
// close to the truth although 10 % of the observations are wrong.
TEST(SolveSchurLm, HuberKeepsWrongMatchesFromPullingTheFit) {
  const PinholeCamera camera = test::TumLikeCamera();
  const test::BaScene scene = test::MakeScene(camera, 6, 300, 2, 0.10, 24, /*noise_scale=*/0.1);
  const StereoIntrinsics k(camera, kBf);
  SchurLmOptions plain, robust;
  robust.robust = true;
  robust.huber_delta_mono = std::sqrt(5.991);
  robust.huber_delta_stereo = std::sqrt(7.815);
  BaState plain_state = StateOf(scene.problem), robust_state = StateOf(scene.problem);
  SolveSchurLm(k, scene.problem, plain, nullptr, &plain_state);
  SolveSchurLm(k, scene.problem, robust, nullptr, &robust_state);
  double plain_error = 0, robust_error = 0;
  for (int i = 2; i < 6; ++i) {
    const Rigid3& truth = scene.truth.keyframes[i].cam_from_world;
    plain_error = std::max(plain_error, test::CentreError(PoseFromBlock(plain_state.poses[i].data()), truth));
    robust_error = std::max(robust_error, test::CentreError(PoseFromBlock(robust_state.poses[i].data()), truth));
  }
  EXPECT_LT(robust_error, 0.5 * plain_error) << plain_error;
}

}  // namespace
}  // namespace esdslam
