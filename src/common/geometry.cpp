#include "common/geometry.h"

#include <cmath>

namespace esdslam {

Mat3 Skew(const Vec3& v) {
  Mat3 m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

Mat3 ExpSO3(const Vec3& phi) {
  const double angle = phi.norm();
  if (angle < 1e-10) return Mat3::Identity() + Skew(phi);
  return Eigen::AngleAxisd(angle, phi / angle).toRotationMatrix();
}

Vec3 LogSO3(const Mat3& rotation) {
  const Eigen::AngleAxisd aa(rotation);
  Vec3 phi = aa.angle() * aa.axis();
  if (phi.norm() > M_PI) phi = phi.normalized() * (phi.norm() - 2.0 * M_PI);
  return phi;
}

namespace {
// Left Jacobian of SO(3) and its inverse.
Mat3 LeftJacobianSO3(const Vec3& phi) {
  const double angle = phi.norm();
  const Mat3 k = Skew(phi);
  if (angle < 1e-8) return Mat3::Identity() + 0.5 * k;
  const double a2 = angle * angle;
  return Mat3::Identity() + (1.0 - std::cos(angle)) / a2 * k + (angle - std::sin(angle)) / (a2 * angle) * k * k;
}
Mat3 InverseLeftJacobianSO3(const Vec3& phi) {
  const double angle = phi.norm();
  const Mat3 k = Skew(phi);
  if (angle < 1e-8) return Mat3::Identity() - 0.5 * k;
  const double half = 0.5 * angle;
  const double coef = (1.0 - half * std::cos(half) / std::sin(half)) / (angle * angle);
  return Mat3::Identity() - 0.5 * k + coef * k * k;
}
}  // namespace

Rigid3 Rigid3::Exp(const Vec6& twist) {
  const Vec3 rho = twist.head<3>();
  const Vec3 phi = twist.tail<3>();
  return Rigid3(ExpSO3(phi), LeftJacobianSO3(phi) * rho);
}

Vec6 Rigid3::Log() const {
  const Vec3 phi = LogSO3(rotation_matrix());
  Vec6 twist;
  twist.head<3>() = InverseLeftJacobianSO3(phi) * translation_;
  twist.tail<3>() = phi;
  return twist;
}

double RotationAngle(const Quat& rotation) {
  // atan2 keeps full precision for tiny angles, where acos(w) rounds to 0.
  return 2.0 * std::atan2(rotation.vec().norm(), std::abs(rotation.w()));
}

}  // namespace esdslam
