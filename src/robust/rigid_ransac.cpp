#include "robust/rigid_ransac.h"

#include <algorithm>
#include <cmath>
#include <random>

#include <Eigen/SVD>

#include "common/error.h"
#include "robust/refine_on_inliers.h"

namespace esdslam {

Sim3Transform Sim3Transform::inverse() const {
  Sim3Transform inv;
  const Quat rotation = rigid.rotation().conjugate();
  inv.scale = 1.0 / scale;
  inv.rigid = Rigid3(rotation, -(inv.scale * (rotation * rigid.translation())));
  return inv;
}

bool AlignPointSets(const std::vector<Vec3>& points_a, const std::vector<Vec3>& points_b, bool estimate_scale,
                    Sim3Transform* a_from_b) {
  const std::size_t n = points_a.size();
  if (n < 3 || points_b.size() != n) return false;
  Vec3 mean_a = Vec3::Zero(), mean_b = Vec3::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    mean_a += points_a[i];
    mean_b += points_b[i];
  }
  mean_a /= static_cast<double>(n);
  mean_b /= static_cast<double>(n);
  Mat3 covariance = Mat3::Zero();  // (1/n) sum (a - mean_a)(b - mean_b)^T
  double variance_b = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 db = points_b[i] - mean_b;
    covariance += (points_a[i] - mean_a) * db.transpose();
    variance_b += db.squaredNorm();
  }
  covariance /= static_cast<double>(n);
  variance_b /= static_cast<double>(n);
  const Eigen::JacobiSVD<Mat3> svd(covariance, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Vec3 singular = svd.singularValues();
  // Rank < 2 (collinear or coincident points): the rotation is not determined.
  if (variance_b <= 1e-18 || singular(1) <= 1e-12 * std::max(1.0, singular(0))) return false;
  Vec3 sign(1.0, 1.0, 1.0);
  if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0.0) sign(2) = -1.0;
  const Mat3 rotation = svd.matrixU() * sign.asDiagonal() * svd.matrixV().transpose();
  const double scale = estimate_scale ? singular.dot(sign) / variance_b : 1.0;
  a_from_b->scale = scale;
  a_from_b->rigid = Rigid3(rotation, Vec3(mean_a - scale * rotation * mean_b));
  return true;
}

void RigidRansacOptions::Check() const {
  if (!(max_error_m > 0.0) || !(max_error_px > 0.0)) throw Error("rigid RANSAC: error thresholds must be positive");
  if (!(confidence > 0.0 && confidence < 1.0)) throw Error("rigid RANSAC: confidence must be in (0, 1)");
  if (max_iterations < 1 || min_inliers < 3 || refine_rounds < 0) throw Error("rigid RANSAC: invalid iteration limits");
}

namespace {

bool ReprojectsWithin(const PinholeCamera& camera, const Vec3& point_cam, const Vec2& pixel, double max_error) {
  if (point_cam.z() <= 0.0) return false;
  return (camera.Project(point_cam) - pixel).squaredNorm() < max_error * max_error;
}

class InlierTest {
 public:
  InlierTest(const RigidRansacOptions& options, const PinholeCamera* camera_a, const PinholeCamera* camera_b)
      : options_(options), camera_a_(camera_a), camera_b_(camera_b) {}

  int Select(const std::vector<PointMatch3D>& matches, const Sim3Transform& a_from_b, std::vector<bool>* inliers) const {
    const Sim3Transform b_from_a = a_from_b.inverse();
    inliers->assign(matches.size(), false);
    int count = 0;
    for (std::size_t i = 0; i < matches.size(); ++i) {
      const PointMatch3D& m = matches[i];
      bool inlier;
      if (options_.mode == RigidRansacOptions::ErrorMode::kMetric) {
        inlier = (m.point_a - a_from_b * m.point_b).norm() < options_.max_error_m;
      } else {
        inlier = ReprojectsWithin(*camera_a_, a_from_b * m.point_b, m.pixel_a, options_.max_error_px * m.pixel_scale_a) &&
                 ReprojectsWithin(*camera_b_, b_from_a * m.point_a, m.pixel_b, options_.max_error_px * m.pixel_scale_b);
      }
      (*inliers)[i] = inlier;
      count += inlier ? 1 : 0;
    }
    return count;
  }

 private:
  const RigidRansacOptions& options_;
  const PinholeCamera* camera_a_;
  const PinholeCamera* camera_b_;
};

bool FitSubset(const std::vector<PointMatch3D>& matches, const std::vector<bool>& use, bool estimate_scale,
               Sim3Transform* a_from_b) {
  std::vector<Vec3> points_a, points_b;
  for (std::size_t i = 0; i < matches.size(); ++i) {
    if (!use[i]) continue;
    points_a.push_back(matches[i].point_a);
    points_b.push_back(matches[i].point_b);
  }
  return AlignPointSets(points_a, points_b, estimate_scale, a_from_b);
}

// Iterations needed so that an all-inlier sample of 3 is drawn with the given confidence.
int RequiredIterations(double inlier_ratio, double confidence, int max_iterations) {
  const double all_inliers = std::pow(inlier_ratio, 3);
  if (all_inliers >= 1.0) return 1;
  if (all_inliers <= 0.0) return max_iterations;
  const double needed = std::log(1.0 - confidence) / std::log(1.0 - all_inliers);
  return static_cast<int>(std::min<double>(max_iterations, std::ceil(needed)));
}

}  // namespace

RigidRansacResult EstimateRigidRansac(const std::vector<PointMatch3D>& matches, const RigidRansacOptions& options,
                                      const PinholeCamera* camera_a, const PinholeCamera* camera_b) {
  options.Check();
  if (options.mode == RigidRansacOptions::ErrorMode::kReprojection && (camera_a == nullptr || camera_b == nullptr))
    throw Error("rigid RANSAC in reprojection mode needs both cameras");
  RigidRansacResult result;
  const int n = static_cast<int>(matches.size());
  if (n < 3) return result;
  const InlierTest test(options, camera_a, camera_b);
  std::mt19937 rng(options.seed);
  std::vector<bool> inliers;
  int needed = options.max_iterations;
  for (int iteration = 0; iteration < needed; ++iteration) {
    ++result.iterations;
    int sample[3];
    sample[0] = static_cast<int>(rng() % n);
    do sample[1] = static_cast<int>(rng() % n); while (sample[1] == sample[0]);
    do sample[2] = static_cast<int>(rng() % n); while (sample[2] == sample[0] || sample[2] == sample[1]);
    Sim3Transform model;
    if (!AlignPointSets({matches[sample[0]].point_a, matches[sample[1]].point_a, matches[sample[2]].point_a},
                        {matches[sample[0]].point_b, matches[sample[1]].point_b, matches[sample[2]].point_b},
                        options.estimate_scale, &model))
      continue;
    const int count = test.Select(matches, model, &inliers);
    if (count > result.num_inliers) {
      result.num_inliers = count;
      result.a_from_b = model;
      result.inliers = inliers;
      needed = RequiredIterations(static_cast<double>(count) / n, options.confidence, options.max_iterations);
    }
  }
  // Refinement: least squares on the inliers, re-select, until the inlier set is stable.
  RefineOnInliers(
      options.refine_rounds, 3,
      [&](const std::vector<bool>& use, Sim3Transform* model) {
        return FitSubset(matches, use, options.estimate_scale, model);
      },
      [&](const Sim3Transform& model, std::vector<bool>* flags) { return test.Select(matches, model, flags); },
      &result.a_from_b, &result.inliers, &result.num_inliers);
  result.success = result.num_inliers >= options.min_inliers;
  return result;
}

}  // namespace esdslam
