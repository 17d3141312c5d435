#include "loop/relative_pose_refinement.h"
#include "optim/small_problem_options.h"

#include <cmath>

#include <ceres/ceres.h>

#include "common/error.h"

namespace esdslam {
namespace {

template <typename T>
void ProjectInto(const PinholeCamera& camera, const Eigen::Matrix<T, 3, 1>& point, T* pixel) {
  pixel[0] = T(camera.fx()) * point.x() / point.z() + T(camera.cx());
  pixel[1] = T(camera.fy()) * point.y() / point.z() + T(camera.cy());
}

// Parameters: quaternion (x, y, z, w) and translation of a_from_b. Residuals (4): view a, view b,
// each (pixel error) / pixel_scale.
struct TwoViewCost {
  TwoViewCost(const PointMatch3D& match, const PinholeCamera& camera_a, const PinholeCamera& camera_b)
      : match_(match), camera_a_(camera_a), camera_b_(camera_b) {}

  template <typename T>
  bool operator()(const T* q_data, const T* t_data, T* residual) const {
    const Eigen::Map<const Eigen::Quaternion<T>> q(q_data);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t(t_data);
    const Eigen::Matrix<T, 3, 1> b_in_a = q * match_.point_b.cast<T>() + t;
    const Eigen::Matrix<T, 3, 1> a_in_b = q.conjugate() * (match_.point_a.cast<T>() - t);
    if (b_in_a.z() <= T(1e-6) || a_in_b.z() <= T(1e-6)) return false;
    T pixel_a[2], pixel_b[2];
    ProjectInto(camera_a_, b_in_a, pixel_a);
    ProjectInto(camera_b_, a_in_b, pixel_b);
    for (int k = 0; k < 2; ++k) {
      residual[k] = (pixel_a[k] - T(match_.pixel_a[k])) / T(match_.pixel_scale_a);
      residual[2 + k] = (pixel_b[k] - T(match_.pixel_b[k])) / T(match_.pixel_scale_b);
    }
    return true;
  }

  PointMatch3D match_;
  const PinholeCamera& camera_a_;
  const PinholeCamera& camera_b_;
};

// Both reprojection chi2 values within the threshold (and both points in front).
bool IsInlier(const PointMatch3D& m, const PinholeCamera& camera_a, const PinholeCamera& camera_b,
              const Rigid3& a_from_b, double chi2) {
  const Vec3 b_in_a = a_from_b * m.point_b;
  const Vec3 a_in_b = a_from_b.inverse() * m.point_a;
  if (b_in_a.z() <= 1e-6 || a_in_b.z() <= 1e-6) return false;
  const double chi2_a = (camera_a.Project(b_in_a) - m.pixel_a).squaredNorm() / (m.pixel_scale_a * m.pixel_scale_a);
  const double chi2_b = (camera_b.Project(a_in_b) - m.pixel_b).squaredNorm() / (m.pixel_scale_b * m.pixel_scale_b);
  return chi2_a <= chi2 && chi2_b <= chi2;
}

void Solve(const std::vector<PointMatch3D>& matches, const std::vector<bool>& use, const PinholeCamera& camera_a,
           const PinholeCamera& camera_b, double huber_delta, int iterations, double* quaternion, double* translation) {
  ceres::Problem problem;
  int residuals = 0;
  for (std::size_t i = 0; i < matches.size(); ++i) {
    if (!use[i]) continue;
    ceres::LossFunction* loss = huber_delta > 0 ? new ceres::HuberLoss(huber_delta) : nullptr;
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<TwoViewCost, 4, 4, 3>(
                                 new TwoViewCost(matches[i], camera_a, camera_b)),
                             loss, quaternion, translation);
    ++residuals;
  }
  if (residuals == 0) return;
  problem.SetManifold(quaternion, new ceres::EigenQuaternionManifold());
  ceres::Solver::Summary summary;
  ceres::Solve(SmallProblemOptions(iterations), &problem, &summary);
}

}  // namespace

void RelativePoseRefinementOptions::Check() const {
  if (!(chi2 > 0)) throw Error("relative pose refinement: chi2 must be positive");
  if (iterations_first < 1 || iterations_second < 0) throw Error("relative pose refinement: invalid iterations");
}

int RefineRelativePose(const std::vector<PointMatch3D>& matches, const PinholeCamera& camera_a,
                       const PinholeCamera& camera_b, const RelativePoseRefinementOptions& options, Rigid3* a_from_b,
                       std::vector<bool>* inliers) {
  options.Check();
  const Quat& q0 = a_from_b->rotation();
  double quaternion[4] = {q0.x(), q0.y(), q0.z(), q0.w()};
  double translation[3] = {a_from_b->translation().x(), a_from_b->translation().y(), a_from_b->translation().z()};
  const auto current = [&] {
    return Rigid3(Quat(quaternion[3], quaternion[0], quaternion[1], quaternion[2]).normalized(),
                  Vec3(translation[0], translation[1], translation[2]));
  };
  // Matches behind a camera at the start cannot be evaluated: they never enter.
  std::vector<bool> use(matches.size());
  for (std::size_t i = 0; i < matches.size(); ++i) use[i] = IsInlier(matches[i], camera_a, camera_b, *a_from_b, 1e30);
  Solve(matches, use, camera_a, camera_b, std::sqrt(options.chi2), options.iterations_first, quaternion, translation);
  int count = 0;
  for (std::size_t i = 0; i < matches.size(); ++i) {
    use[i] = IsInlier(matches[i], camera_a, camera_b, current(), options.chi2);
    count += use[i] ? 1 : 0;
  }
  if (options.iterations_second > 0 && count >= 3)
    Solve(matches, use, camera_a, camera_b, 0.0, options.iterations_second, quaternion, translation);
  *a_from_b = current();
  count = 0;
  std::vector<bool> final_inliers(matches.size());
  for (std::size_t i = 0; i < matches.size(); ++i) {
    final_inliers[i] = IsInlier(matches[i], camera_a, camera_b, *a_from_b, options.chi2);
    count += final_inliers[i] ? 1 : 0;
  }
  if (inliers != nullptr) *inliers = std::move(final_inliers);
  return count;
}

}  // namespace esdslam
