#include "optim/reprojection_cost.h"

#include <random>

#include <gtest/gtest.h>

#include "optim/optim_test_scene.h"

namespace esdslam {
namespace {

constexpr double kStep = 1e-6;

// Central differences of a cost's residual w.r.t. the pose tangent (through PoseManifold::Plus)
// and, when it has one, the point block; compared to the analytic Jacobians.
template <int kResiduals>
void CheckJacobians(const ceres::CostFunction& cost, const double* pose, const double* point) {
  const PoseManifold manifold;
  const int blocks = point == nullptr ? 1 : 2;
  double jac_pose[kResiduals * 7], jac_point[kResiduals * 3], residual[kResiduals];
  double* jacobians[2] = {jac_pose, jac_point};
  const double* params[2] = {pose, point};
  ASSERT_TRUE(cost.Evaluate(params, residual, jacobians));
  for (int k = 0; k < 6; ++k) {
    double delta[6] = {0, 0, 0, 0, 0, 0}, plus[7], minus[7], r_plus[kResiduals], r_minus[kResiduals];
    delta[k] = kStep;
    manifold.Plus(pose, delta, plus);
    delta[k] = -kStep;
    manifold.Plus(pose, delta, minus);
    const double* p_plus[2] = {plus, point};
    const double* p_minus[2] = {minus, point};
    ASSERT_TRUE(cost.Evaluate(p_plus, r_plus, nullptr));
    ASSERT_TRUE(cost.Evaluate(p_minus, r_minus, nullptr));
    for (int r = 0; r < kResiduals; ++r)
      EXPECT_NEAR(jac_pose[r * 7 + k], (r_plus[r] - r_minus[r]) / (2 * kStep), 1e-4) << "pose " << r << "," << k;
  }
  for (int r = 0; r < kResiduals; ++r) EXPECT_EQ(jac_pose[r * 7 + 6], 0.0);
  if (blocks == 1) return;
  for (int k = 0; k < 3; ++k) {
    double plus[3] = {point[0], point[1], point[2]}, minus[3] = {point[0], point[1], point[2]};
    plus[k] += kStep;
    minus[k] -= kStep;
    double r_plus[kResiduals], r_minus[kResiduals];
    const double* p_plus[2] = {pose, plus};
    const double* p_minus[2] = {pose, minus};
    ASSERT_TRUE(cost.Evaluate(p_plus, r_plus, nullptr));
    ASSERT_TRUE(cost.Evaluate(p_minus, r_minus, nullptr));
    for (int r = 0; r < kResiduals; ++r)
      EXPECT_NEAR(jac_point[r * 3 + k], (r_plus[r] - r_minus[r]) / (2 * kStep), 1e-4) << "point " << r << "," << k;
  }
}

class ReprojectionCostTest : public ::testing::Test {
 protected:
  PinholeCamera camera_ = test::TumLikeCamera();
  StereoIntrinsics k_{camera_, test::kBf};
  Rigid3 cam_from_world_ = Rigid3(ExpSO3(Vec3(0.2, 0.4, -0.1)), Vec3(0.3, -0.1, 0.5));
  Vec3 point_world_ = Vec3(0.4, -0.3, 2.5);
  ReprojectionMeasurement mono_{Vec2(300, 200), -1, 0.8};
  ReprojectionMeasurement stereo_{Vec2(300, 200), 290, 0.8};
};

TEST_F(ReprojectionCostTest, AnalyticJacobiansMatchNumericOnes) {
  double pose[7];
  PoseToBlock(cam_from_world_, pose);
  ASSERT_GT((cam_from_world_ * point_world_).z(), 0.5);
  CheckJacobians<2>(PosePointCost<2>(k_, mono_), pose, point_world_.data());
  CheckJacobians<3>(PosePointCost<3>(k_, stereo_), pose, point_world_.data());
}

// The Ceres-free evaluation (our solvers) equals the Ceres cost function checked above.
template <int kResiduals>
void ExpectSameAsPosePointCost(const StereoIntrinsics& k, const ReprojectionMeasurement& m, const double* pose,
                               const Vec3& point_world) {
  Eigen::Matrix<double, kResiduals, 1> residual;
  Eigen::Matrix<double, kResiduals, 6> jacobian_pose;
  Eigen::Matrix<double, kResiduals, 3> jacobian_point;
  ASSERT_TRUE(EvaluateReprojection<kResiduals>(k, m, pose, point_world, &residual, &jacobian_pose, &jacobian_point));
  double ceres_residual[kResiduals], ceres_pose[kResiduals * 7], ceres_point[kResiduals * 3];
  double* jacobians[2] = {ceres_pose, ceres_point};
  const double* params[2] = {pose, point_world.data()};
  ASSERT_TRUE(PosePointCost<kResiduals>(k, m).Evaluate(params, ceres_residual, jacobians));
  for (int r = 0; r < kResiduals; ++r) {
    EXPECT_NEAR(residual(r), ceres_residual[r], 1e-12);
    for (int c = 0; c < 6; ++c) EXPECT_NEAR(jacobian_pose(r, c), ceres_pose[r * 7 + c], 1e-9);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(jacobian_point(r, c), ceres_point[r * 3 + c], 1e-9);
  }
  Eigen::Matrix<double, kResiduals, 1> residual_only;
  ASSERT_TRUE(EvaluateReprojection<kResiduals>(k, m, pose, point_world, &residual_only, nullptr, nullptr));
  EXPECT_EQ(residual_only, residual);
  double behind[7];
  PoseToBlock(Rigid3(Quat::Identity(), Vec3(0, 0, -10)), behind);
  EXPECT_FALSE(EvaluateReprojection<kResiduals>(k, m, behind, point_world, &residual_only, nullptr, nullptr));
}

TEST_F(ReprojectionCostTest, EvaluateReprojectionMatchesTheCeresCost) {
  double pose[7];
  PoseToBlock(cam_from_world_, pose);
  ExpectSameAsPosePointCost<2>(k_, mono_, pose, point_world_);
  ExpectSameAsPosePointCost<3>(k_, stereo_, pose, point_world_);
}

TEST_F(ReprojectionCostTest, ResidualIsTheWeightedReprojectionError) {
  const Vec3 p = cam_from_world_ * point_world_;
  const Vec2 uv = camera_.Project(p);
  ReprojectionMeasurement m{uv + Vec2(1.5, -2.0), uv.x() - test::kBf / p.z() + 0.5, 2.0};
  bool in_front = false;
  EXPECT_NEAR(ReprojectionChi2(k_, m, cam_from_world_, point_world_, &in_front),
              4.0 * (1.5 * 1.5 + 2.0 * 2.0 + 0.5 * 0.5), 1e-9);
  EXPECT_TRUE(in_front);
  m.right_u = -1;
  EXPECT_NEAR(ReprojectionChi2(k_, m, cam_from_world_, point_world_, &in_front), 4.0 * (1.5 * 1.5 + 2.0 * 2.0),
              1e-9);
  const Vec3 behind = cam_from_world_.inverse() * Vec3(-p);
  EXPECT_TRUE(std::isinf(ReprojectionChi2(k_, m, cam_from_world_, behind, &in_front)));
  EXPECT_FALSE(in_front);
}

TEST_F(ReprojectionCostTest, ManifoldPlusAndMinusAreInverse) {
  const PoseManifold manifold;
  double x[7], y[7], back[6];
  PoseToBlock(cam_from_world_, x);
  const double delta[6] = {0.1, -0.05, 0.2, 0.3, -0.2, 0.1};
  ASSERT_TRUE(manifold.Plus(x, delta, y));
  ASSERT_TRUE(manifold.Minus(y, x, back));
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(back[i], delta[i], 1e-12);
  // Plus applies the twist on the left: y = (Exp(phi), rho) * x.
  const Rigid3 expected = Rigid3(ExpSO3(Vec3(0.3, -0.2, 0.1)), Vec3(0.1, -0.05, 0.2)) * cam_from_world_;
  EXPECT_LT((PoseFromBlock(y).matrix() - expected.matrix()).norm(), 1e-12);
}

}  // namespace
}  // namespace esdslam
