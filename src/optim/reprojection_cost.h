#pragma once
// Shared pieces of the optimisers in optim/ (our Levenberg-Marquardt solvers and the Ceres
// problems): the pose parameter block with its manifold and the reprojection residuals of
// ORB-SLAM2's RGB-D edges, with analytic Jacobians.
//
// Pose block (7 doubles): cam_from_world as quaternion (x, y, z, w) then translation (m).
// Tangent (6): delta = (rho, phi) applied on the left: R' = Exp(phi) R, t' = Exp(phi) t + rho,
// so at delta = 0 a camera-frame point p moves as d p / d delta = [I, -[p]x].
// The cost functions fill the first 6 columns of the 7-column pose Jacobian with the Jacobian
// w.r.t. the tangent and leave the 7th zero; PoseManifold::PlusJacobian is [I6; 0], so Ceres'
// product of the two is exactly the tangent Jacobian.
//
// Residual (weighted by sqrt(information), so its squared norm is the chi2 statistic):
//   mono (2):   (u - u_proj, v - v_proj)
//   stereo (3): (u - u_proj, v - v_proj, right_u - (u_proj - bf / z_cam))

#include <ceres/ceres.h>

#include "camera/pinhole_camera.h"
#include "common/geometry.h"

namespace esdslam {

using Mat6 = Eigen::Matrix<double, 6, 6>;

constexpr int kPoseBlockSize = 7;
constexpr int kPoseTangentSize = 6;
// Points closer than this (m, along the optical axis) count as behind the camera.
constexpr double kMinPositiveDepth = 1e-6;

void PoseToBlock(const Rigid3& cam_from_world, double* block);
Rigid3 PoseFromBlock(const double* block);

class PoseManifold final : public ceres::Manifold {
 public:
  int AmbientSize() const override { return kPoseBlockSize; }
  int TangentSize() const override { return kPoseTangentSize; }
  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override;
  bool PlusJacobian(const double* x, double* jacobian) const override;
  bool Minus(const double* y, const double* x, double* y_minus_x) const override;
  bool MinusJacobian(const double* x, double* jacobian) const override;
};

// Intrinsics needed by the residuals (undistorted pinhole) plus bf (baseline * fx, px m).
struct StereoIntrinsics {
  double fx, fy, cx, cy, bf;
  StereoIntrinsics(const PinholeCamera& camera, double bf_)
      : fx(camera.fx()), fy(camera.fy()), cx(camera.cx()), cy(camera.cy()), bf(bf_) {}
};

// One observation's measurement as the residuals see it.
struct ReprojectionMeasurement {
  Vec2 pixel;
  double right_u = -1;  // < 0: mono
  double sqrt_information = 1;
  bool stereo() const { return right_u >= 0; }
};

// Weighted residual at a camera-frame point; if d_residual_d_point is not null it receives the
// kResiduals x 3 row-major Jacobian w.r.t. the camera-frame point. Returns false when
// z <= kMinPositiveDepth.
template <int kResiduals>
bool ReprojectionResidual(const StereoIntrinsics& k, const ReprojectionMeasurement& m, const Vec3& point_cam,
                          double* residual, double* d_residual_d_point);

// Weighted residual of an observation at a pose block (cam_from_world) and a world point; if
// jacobian_pose is not null, also the Jacobians w.r.t. the pose tangent (left perturbation, as
// above) and, if jacobian_point is not null, the world point. False when the point is not in
// front of the camera.
template <int kResiduals>
bool EvaluateReprojection(const StereoIntrinsics& k, const ReprojectionMeasurement& m, const double* pose_block,
                          const Vec3& point_world, Eigen::Matrix<double, kResiduals, 1>* residual,
                          Eigen::Matrix<double, kResiduals, 6>* jacobian_pose,
                          Eigen::Matrix<double, kResiduals, 3>* jacobian_point) {
  const Mat3 rotation = Eigen::Map<const Quat>(pose_block).toRotationMatrix();
  const Vec3 point_cam = rotation * point_world + Eigen::Map<const Vec3>(pose_block + 4);
  Eigen::Matrix<double, kResiduals, 3, Eigen::RowMajor> d_point;
  if (!ReprojectionResidual<kResiduals>(k, m, point_cam, residual->data(),
                                        jacobian_pose != nullptr ? d_point.data() : nullptr))
    return false;
  if (jacobian_pose == nullptr) return true;
  jacobian_pose->template leftCols<3>() = d_point;
  jacobian_pose->template rightCols<3>() = -d_point * Skew(point_cam);
  if (jacobian_point != nullptr) *jacobian_point = d_point * rotation;
  return true;
}

// chi2 (squared weighted residual) of an observation at given estimates; sets *in_front to
// whether the point is in front of the camera (chi2 is +inf otherwise).
double ReprojectionChi2(const StereoIntrinsics& k, const ReprojectionMeasurement& m, const Rigid3& cam_from_world,
                        const Vec3& point_world, bool* in_front);

// Residual with pose and point (world, 3) blocks (bundle adjustment).
template <int kResiduals>
class PosePointCost final : public ceres::SizedCostFunction<kResiduals, kPoseBlockSize, 3> {
 public:
  PosePointCost(const StereoIntrinsics& k, const ReprojectionMeasurement& m) : k_(k), m_(m) {}
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

 private:
  StereoIntrinsics k_;
  ReprojectionMeasurement m_;
};

// Allocates the mono or stereo variant for the measurement (caller owns it).
ceres::CostFunction* NewPosePointCost(const StereoIntrinsics& k, const ReprojectionMeasurement& m);

}  // namespace esdslam
