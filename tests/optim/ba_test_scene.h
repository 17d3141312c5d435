#pragma once
// Bundle-adjustment windows with known answers, shared by the BundleAdjust and SolveSchurLm tests.

#include <cmath>
#include <random>
#include <vector>

#include "optim/bundle_adjustment.h"
#include "optim/optim_test_scene.h"

namespace esdslam::test {

struct BaScene {
  BaProblem truth;    // exact poses and points
  BaProblem problem;  // noisy observations, perturbed estimates
  std::vector<bool> is_outlier;
};

// Keyframes on a 1 m arc looking at points 2-6 m away; every point is observed by the
// keyframes that see it (pixel noise noise_scale * 0.5 px * 1.2^level; half of them with depth).
// The first `fixed` keyframes stay at the truth; the others are perturbed by 3 cm / 1.5 deg,
// points by 5 cm (isotropic). `outlier_fraction` of the observations are wrong matches.
inline BaScene MakeScene(const PinholeCamera& camera, int keyframes, int points, int fixed, double outlier_fraction,
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
      const KeypointNoise noise = RandomLevel(&rng);
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
    kf.cam_from_world = RandomPerturbation(0.03, 1.5, &rng) * kf.cam_from_world;
  }
  for (BaPoint& point : scene.problem.points)
    point.position_world += 0.05 / std::sqrt(3.0) * Vec3(normal(rng), normal(rng), normal(rng));
  return scene;
}

// RMS of the unweighted reprojection error (left image) over the true inliers.
inline double ReprojectionRms(const PinholeCamera& camera, const BaProblem& problem, const std::vector<bool>& is_outlier) {
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

}  // namespace esdslam::test
