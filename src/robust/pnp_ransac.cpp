#include "robust/pnp_ransac.h"

#include <algorithm>
#include <cmath>
#include <random>

#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

#include "common/error.h"
#include "robust/refine_on_inliers.h"

namespace esdslam {

void PnpRansacOptions::Check() const {
  if (!(max_error_px > 0.0)) throw Error("PnP RANSAC: max_error_px must be positive");
  if (!(confidence > 0.0 && confidence < 1.0)) throw Error("PnP RANSAC: confidence must be in (0, 1)");
  if (max_iterations < 1 || min_inliers < 4 || refine_rounds < 0) throw Error("PnP RANSAC: invalid iteration limits");
}

namespace {

class PnpProblem {
 public:
  PnpProblem(const std::vector<Vec3>& points, const std::vector<Vec2>& pixels, const PinholeCamera& camera,
             const std::vector<double>& scales, double max_error_px)
      : points_(points), pixels_(pixels), camera_(camera), scales_(scales), max_error_px_(max_error_px) {
    camera_matrix_ = camera.intrinsics().CameraMatrix();
  }

  // Solves from the selected matches; `minimal` uses AP3P on exactly 4 of them.
  bool Solve(const std::vector<int>& selected, bool minimal, Rigid3* cam_from_world) const {
    std::vector<cv::Point3d> object;
    std::vector<cv::Point2d> image;
    for (const int i : selected) {
      object.emplace_back(points_[i].x(), points_[i].y(), points_[i].z());
      image.emplace_back(pixels_[i].x(), pixels_[i].y());
    }
    cv::Mat rvec, tvec;
    bool ok;
    if (minimal) {
      ok = cv::solvePnP(object, image, camera_matrix_, cv::noArray(), rvec, tvec, false, cv::SOLVEPNP_AP3P);
    } else {
      ToCv(*cam_from_world, &rvec, &tvec);
      ok = cv::solvePnP(object, image, camera_matrix_, cv::noArray(), rvec, tvec, true, cv::SOLVEPNP_ITERATIVE);
    }
    if (!ok || rvec.empty()) return false;
    Vec3 rotation_vector, translation;
    cv::cv2eigen(rvec.reshape(1, 3), rotation_vector);
    cv::cv2eigen(tvec.reshape(1, 3), translation);
    if (!rotation_vector.allFinite() || !translation.allFinite()) return false;
    *cam_from_world = Rigid3(ExpSO3(rotation_vector), translation);
    return true;
  }

  int Select(const Rigid3& cam_from_world, std::vector<bool>* inliers) const {
    inliers->assign(points_.size(), false);
    int count = 0;
    for (std::size_t i = 0; i < points_.size(); ++i) {
      const Vec3 p = cam_from_world * points_[i];
      if (p.z() <= 0.0) continue;
      const double threshold = max_error_px_ * (scales_.empty() ? 1.0 : scales_[i]);
      if ((camera_.Project(p) - pixels_[i]).squaredNorm() < threshold * threshold) {
        (*inliers)[i] = true;
        ++count;
      }
    }
    return count;
  }

 private:
  static void ToCv(const Rigid3& pose, cv::Mat* rvec, cv::Mat* tvec) {
    const Vec3 r = LogSO3(pose.rotation_matrix());
    *rvec = (cv::Mat_<double>(3, 1) << r.x(), r.y(), r.z());
    *tvec = (cv::Mat_<double>(3, 1) << pose.translation().x(), pose.translation().y(), pose.translation().z());
  }

  const std::vector<Vec3>& points_;
  const std::vector<Vec2>& pixels_;
  const PinholeCamera& camera_;
  const std::vector<double>& scales_;
  const double max_error_px_;
  cv::Mat camera_matrix_;
};

std::vector<int> Indices(const std::vector<bool>& flags) {
  std::vector<int> out;
  for (std::size_t i = 0; i < flags.size(); ++i) {
    if (flags[i]) out.push_back(static_cast<int>(i));
  }
  return out;
}

}  // namespace

PnpRansacResult EstimatePnpRansac(const std::vector<Vec3>& points_world, const std::vector<Vec2>& pixels,
                                  const PinholeCamera& camera, const PnpRansacOptions& options,
                                  const std::vector<double>& pixel_scales) {
  options.Check();
  if (pixels.size() != points_world.size() || (!pixel_scales.empty() && pixel_scales.size() != pixels.size()))
    throw Error("PnP RANSAC: points, pixels and scales must have the same length");
  PnpRansacResult result;
  const int n = static_cast<int>(points_world.size());
  if (n < 4) return result;
  const PnpProblem problem(points_world, pixels, camera, pixel_scales, options.max_error_px);
  std::mt19937 rng(options.seed);
  std::vector<bool> inliers;
  int needed = options.max_iterations;
  for (int iteration = 0; iteration < needed; ++iteration) {
    ++result.iterations;
    std::vector<int> sample;
    while (sample.size() < 4) {
      const int pick = static_cast<int>(rng() % n);
      if (std::find(sample.begin(), sample.end(), pick) == sample.end()) sample.push_back(pick);
    }
    Rigid3 model;
    if (!problem.Solve(sample, true, &model)) continue;
    const int count = problem.Select(model, &inliers);
    if (count <= result.num_inliers) continue;
    result.num_inliers = count;
    result.cam_from_world = model;
    result.inliers = inliers;
    const double all_inliers = std::pow(static_cast<double>(count) / n, 4);
    needed = all_inliers >= 1.0 ? iteration + 1
                                : static_cast<int>(std::min<double>(
                                      options.max_iterations,
                                      std::ceil(std::log(1.0 - options.confidence) / std::log(1.0 - all_inliers))));
  }
  RefineOnInliers(
      options.refine_rounds, 4,
      [&](const std::vector<bool>& use, Rigid3* model) { return problem.Solve(Indices(use), false, model); },
      [&](const Rigid3& model, std::vector<bool>* flags) { return problem.Select(model, flags); },
      &result.cam_from_world, &result.inliers, &result.num_inliers);
  result.success = result.num_inliers >= options.min_inliers;
  return result;
}

}  // namespace esdslam
