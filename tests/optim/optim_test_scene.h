#pragma once
// Synthetic correspondences with known answers for the optimiser tests.

#include <cmath>
#include <random>

#include "camera/pinhole_camera.h"
#include "common/geometry.h"

namespace esdslam::test {

inline PinholeCamera TumLikeCamera() {
  CameraIntrinsics intrinsics;
  intrinsics.fx = 517.3;
  intrinsics.fy = 516.5;
  intrinsics.cx = 318.6;
  intrinsics.cy = 255.3;
  return PinholeCamera(intrinsics);
}
constexpr double kBf = 40.0;  // ORB-SLAM2's TUM setting: baseline 0.077 m * fx

// Random rigid motion with the given translation (m) and rotation (deg) magnitudes.
inline Rigid3 RandomPerturbation(double translation, double rotation_deg, std::mt19937* rng) {
  std::normal_distribution<double> normal(0, 1);
  Vec3 t(normal(*rng), normal(*rng), normal(*rng));
  Vec3 axis(normal(*rng), normal(*rng), normal(*rng));
  return Rigid3(ExpSO3(axis.normalized() * rotation_deg * M_PI / 180), t.normalized() * translation);
}

// Centre distance (m) and rotation angle (deg) between two cam_from_world poses.
inline double CentreError(const Rigid3& a, const Rigid3& b) {
  return (a.inverse().translation() - b.inverse().translation()).norm();
}
inline double RotationErrorDeg(const Rigid3& a, const Rigid3& b) {
  return RotationAngle(a.rotation() * b.rotation().conjugate()) * 180 / M_PI;
}

// Pyramid level and its sigma (px) for a keypoint: sigma = 0.5 px * 1.2^level.
struct KeypointNoise {
  int level;
  double sigma;
  double information;  // 1 / (1.2^level)^2, as ORB-SLAM2's inverse level sigma^2
};
inline KeypointNoise RandomLevel(std::mt19937* rng) {
  std::uniform_int_distribution<int> level_dist(0, 3);
  const int level = level_dist(*rng);
  const double scale = std::pow(1.2, level);
  return {level, 0.5 * scale, 1.0 / (scale * scale)};
}

}  // namespace esdslam::test
