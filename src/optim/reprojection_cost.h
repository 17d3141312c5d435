#pragma once
// Shared pieces of the Ceres problems in optim/: the pose parameter block with its manifold and
// the reprojection residuals of ORB-SLAM2's RGB-D edges, with analytic Jacobians.
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

// chi2 (squared weighted residual) of an observation at given estimates; sets *in_front to
// whether the point is in front of the camera (chi2 is +inf otherwise).
double ReprojectionChi2(const StereoIntrinsics& k, const ReprojectionMeasurement& m, const Rigid3& cam_from_world,
                        const Vec3& point_world, bool* in_front);

// Residual with the pose as the only parameter block (motion-only BA).
template <int kResiduals>
class PoseOnlyCost final : public ceres::SizedCostFunction<kResiduals, kPoseBlockSize> {
 public:
  PoseOnlyCost(const StereoIntrinsics& k, const ReprojectionMeasurement& m, const Vec3& point_world)
      : k_(k), m_(m), point_world_(point_world) {}
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

 private:
  StereoIntrinsics k_;
  ReprojectionMeasurement m_;
  Vec3 point_world_;
};

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
ceres::CostFunction* NewPoseOnlyCost(const StereoIntrinsics& k, const ReprojectionMeasurement& m,
                                     const Vec3& point_world);
ceres::CostFunction* NewPosePointCost(const StereoIntrinsics& k, const ReprojectionMeasurement& m);

}  // namespace esdslam
