#include "optim/reprojection_cost.h"

#include <cmath>
#include <limits>

namespace esdslam {

void PoseToBlock(const Rigid3& cam_from_world, double* block) {
  const Quat& q = cam_from_world.rotation();
  block[0] = q.x();
  block[1] = q.y();
  block[2] = q.z();
  block[3] = q.w();
  Eigen::Map<Vec3> translation(block + 4);
  translation = cam_from_world.translation();
}

Rigid3 PoseFromBlock(const double* block) {
  return Rigid3(Quat(block[3], block[0], block[1], block[2]), Vec3(block[4], block[5], block[6]));
}

namespace {
// Unit quaternion of the rotation vector phi (rad).
Quat QuatExp(const Vec3& phi) {
  const double angle = phi.norm();
  if (angle < 1e-10) return Quat(1.0, 0.5 * phi.x(), 0.5 * phi.y(), 0.5 * phi.z()).normalized();
  const Vec3 axis_sin = std::sin(0.5 * angle) / angle * phi;
  return Quat(std::cos(0.5 * angle), axis_sin.x(), axis_sin.y(), axis_sin.z());
}
}  // namespace

bool PoseManifold::Plus(const double* x, const double* delta, double* x_plus_delta) const {
  const Eigen::Map<const Quat> q(x);
  const Eigen::Map<const Vec3> t(x + 4);
  const Eigen::Map<const Vec3> rho(delta), phi(delta + 3);
  const Quat dq = QuatExp(phi);
  Eigen::Map<Quat> q_out(x_plus_delta);
  Eigen::Map<Vec3> t_out(x_plus_delta + 4);
  q_out = (dq * q).normalized();
  t_out = dq * t + rho;
  return true;
}

bool PoseManifold::PlusJacobian(const double* /*x*/, double* jacobian) const {
  Eigen::Map<Eigen::Matrix<double, 7, 6, Eigen::RowMajor>> j(jacobian);
  j.setZero();
  j.topRows<6>().setIdentity();
  return true;
}

bool PoseManifold::Minus(const double* y, const double* x, double* y_minus_x) const {
  const Eigen::Map<const Quat> qx(x), qy(y);
  const Eigen::Map<const Vec3> tx(x + 4), ty(y + 4);
  const Quat dq = qy * qx.conjugate();
  Eigen::Map<Vec3> rho(y_minus_x), phi(y_minus_x + 3);
  rho = ty - dq * tx;
  phi = LogSO3(dq.toRotationMatrix());
  return true;
}

bool PoseManifold::MinusJacobian(const double* /*x*/, double* jacobian) const {
  Eigen::Map<Eigen::Matrix<double, 6, 7, Eigen::RowMajor>> j(jacobian);
  j.setZero();
  j.leftCols<6>().setIdentity();
  return true;
}

template <int kResiduals>
bool ReprojectionResidual(const StereoIntrinsics& k, const ReprojectionMeasurement& m, const Vec3& point_cam,
                          double* residual, double* d_residual_d_point) {
  const double z = point_cam.z();
  if (!(z > kMinPositiveDepth)) return false;
  const double inv_z = 1.0 / z;
  const double x_n = point_cam.x() * inv_z, y_n = point_cam.y() * inv_z;
  const double u_proj = k.fx * x_n + k.cx;
  const double w = m.sqrt_information;
  residual[0] = w * (m.pixel.x() - u_proj);
  residual[1] = w * (m.pixel.y() - (k.fy * y_n + k.cy));
  if (kResiduals == 3) residual[2] = w * (m.right_u - (u_proj - k.bf * inv_z));
  if (d_residual_d_point != nullptr) {
    Eigen::Map<Eigen::Matrix<double, kResiduals, 3, Eigen::RowMajor>> j(d_residual_d_point);
    // residual = w * (measured - projected): Jacobian is -w * d projected / d point.
    j.row(0) << -w * k.fx * inv_z, 0, w * k.fx * x_n * inv_z;
    j.row(1) << 0, -w * k.fy * inv_z, w * k.fy * y_n * inv_z;
    if (kResiduals == 3) j.row(kResiduals - 1) << -w * k.fx * inv_z, 0, w * (k.fx * x_n - k.bf * inv_z) * inv_z;
  }
  return true;
}

template bool ReprojectionResidual<2>(const StereoIntrinsics&, const ReprojectionMeasurement&, const Vec3&,
                                      double*, double*);
template bool ReprojectionResidual<3>(const StereoIntrinsics&, const ReprojectionMeasurement&, const Vec3&,
                                      double*, double*);

double ReprojectionChi2(const StereoIntrinsics& k, const ReprojectionMeasurement& m, const Rigid3& cam_from_world,
                        const Vec3& point_world, bool* in_front) {
  const Vec3 point_cam = cam_from_world * point_world;
  double residual[3] = {0, 0, 0};
  *in_front = m.stereo() ? ReprojectionResidual<3>(k, m, point_cam, residual, nullptr)
                         : ReprojectionResidual<2>(k, m, point_cam, residual, nullptr);
  if (!*in_front) return std::numeric_limits<double>::infinity();
  return residual[0] * residual[0] + residual[1] * residual[1] + residual[2] * residual[2];
}

namespace {

// Camera-frame point and the rotation of a pose block.
Vec3 TransformByBlock(const double* pose, const Vec3& point_world, Mat3* rotation) {
  const Eigen::Map<const Quat> q(pose);
  *rotation = q.toRotationMatrix();
  return *rotation * point_world + Eigen::Map<const Vec3>(pose + 4);
}

// Writes the 6-column tangent Jacobian into the first 6 of 7 columns (see the header).
template <int kResiduals>
void FillPoseJacobian(const Eigen::Matrix<double, kResiduals, 3, Eigen::RowMajor>& d_point, const Vec3& point_cam,
                      double* jacobian) {
  Eigen::Map<Eigen::Matrix<double, kResiduals, kPoseBlockSize, Eigen::RowMajor>> j(jacobian);
  j.template leftCols<3>() = d_point;
  j.template middleCols<3>(3) = -d_point * Skew(point_cam);
  j.col(6).setZero();
}

}  // namespace

template <int kResiduals>
bool PosePointCost<kResiduals>::Evaluate(double const* const* parameters, double* residuals,
                                         double** jacobians) const {
  Mat3 rotation;
  const Vec3 point_world = Eigen::Map<const Vec3>(parameters[1]);
  const Vec3 point_cam = TransformByBlock(parameters[0], point_world, &rotation);
  Eigen::Matrix<double, kResiduals, 3, Eigen::RowMajor> d_point;
  const bool want_jacobian = jacobians != nullptr && (jacobians[0] != nullptr || jacobians[1] != nullptr);
  if (!ReprojectionResidual<kResiduals>(k_, m_, point_cam, residuals, want_jacobian ? d_point.data() : nullptr))
    return false;
  if (!want_jacobian) return true;
  if (jacobians[0] != nullptr) FillPoseJacobian<kResiduals>(d_point, point_cam, jacobians[0]);
  if (jacobians[1] != nullptr) {
    Eigen::Map<Eigen::Matrix<double, kResiduals, 3, Eigen::RowMajor>> d_world(jacobians[1]);
    d_world = d_point * rotation;
  }
  return true;
}

template class PosePointCost<2>;
template class PosePointCost<3>;

ceres::CostFunction* NewPosePointCost(const StereoIntrinsics& k, const ReprojectionMeasurement& m) {
  if (m.stereo()) return new PosePointCost<3>(k, m);
  return new PosePointCost<2>(k, m);
}

}  // namespace esdslam
