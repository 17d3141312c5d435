#pragma once
// Rigid-body transforms. Naming convention used across the project: `a_from_b` maps
// coordinates expressed in frame b into frame a (p_a = a_from_b * p_b). "world" is the map
// frame (the first keyframe's camera frame unless stated otherwise), "cam" a camera frame with
// x right, y down, z forward (OpenCV convention). Units are metres and radians.

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace esdslam {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat3 = Eigen::Matrix3d;
using Mat4 = Eigen::Matrix4d;
using Quat = Eigen::Quaterniond;

// A rigid transform (rotation + translation), stored as quaternion and vector.
class Rigid3 {
 public:
  Rigid3() : rotation_(Quat::Identity()), translation_(Vec3::Zero()) {}
  Rigid3(const Quat& rotation, const Vec3& translation)
      : rotation_(rotation.normalized()), translation_(translation) {}
  Rigid3(const Mat3& rotation, const Vec3& translation)
      : rotation_(Quat(rotation).normalized()), translation_(translation) {}

  static Rigid3 Identity() { return Rigid3(); }
  static Rigid3 FromMatrix(const Mat4& m) {
    return Rigid3(Mat3(m.topLeftCorner<3, 3>()), Vec3(m.topRightCorner<3, 1>()));
  }

  const Quat& rotation() const { return rotation_; }
  const Vec3& translation() const { return translation_; }
  Mat3 rotation_matrix() const { return rotation_.toRotationMatrix(); }
  Mat4 matrix() const {
    Mat4 m = Mat4::Identity();
    m.topLeftCorner<3, 3>() = rotation_matrix();
    m.topRightCorner<3, 1>() = translation_;
    return m;
  }

  Rigid3 inverse() const {
    const Quat inv = rotation_.conjugate();
    return Rigid3(inv, -(inv * translation_));
  }
  Rigid3 operator*(const Rigid3& other) const {
    return Rigid3(rotation_ * other.rotation_, rotation_ * other.translation_ + translation_);
  }
  Vec3 operator*(const Vec3& point) const { return rotation_ * point + translation_; }

  // Exponential map of a twist (rho: translation part, phi: rotation vector) -> transform.
  // Uses the SE(3) left Jacobian so that Exp(Log(T)) == T.
  static Rigid3 Exp(const Vec6& twist);
  // Logarithm: (rho, phi) with |phi| <= pi.
  Vec6 Log() const;

 private:
  Quat rotation_;
  Vec3 translation_;
};

// Rotation vector (axis * angle) <-> rotation matrix, numerically safe near zero.
Mat3 ExpSO3(const Vec3& phi);
Vec3 LogSO3(const Mat3& rotation);
Mat3 Skew(const Vec3& v);

// Angle of a rotation in radians, in [0, pi].
double RotationAngle(const Quat& rotation);

}  // namespace esdslam
