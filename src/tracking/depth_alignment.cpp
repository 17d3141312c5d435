#include "tracking/depth_alignment.h"

#include <cmath>
#include <vector>

#include <Eigen/Cholesky>

#include "common/error.h"

namespace esdslam {

void DepthAlignmentOptions::Check() const {
  if (sample_stride_px < 1) throw Error("depth alignment: sample stride must be >= 1 px");
  if (!(min_depth_m > 0) || !(max_depth_m > min_depth_m)) throw Error("depth alignment: need 0 < min depth < max depth");
  if (!(depth_noise_at_1m > 0)) throw Error("depth alignment: depth noise must be positive");
  if (!(gate_sigmas > 0)) throw Error("depth alignment: gate must be positive");
  if (!(same_surface_ratio > 0)) throw Error("depth alignment: same-surface ratio must be positive");
  if (iterations < 1 || min_samples < 6) throw Error("depth alignment: iterations >= 1, min samples >= 6");
}

namespace {

using Mat6 = Eigen::Matrix<double, 6, 6>;

struct Sample {
  Vec3 point_cam;  // the frame's camera frame, m
  double sigma2;   // its depth noise variance, m^2
};

// The reference's static reading at the raw pixel nearest to `point_ref`'s projection, with the
// surface normal from its 4-neighbours 2 px away (all on one surface), facing the camera.
struct SurfaceHit {
  double depth;
  Vec3 point;   // the reading's point, reference camera frame
  Vec3 normal;  // unit, facing the camera
};

std::optional<SurfaceHit> ReferenceSurface(const PinholeCamera& camera, const cv::Mat& depth_m, const cv::Mat& mask,
                                           const Vec3& point_ref, const DepthAlignmentOptions& options) {
  if (!(point_ref.z() > options.min_depth_m)) return std::nullopt;
  const Vec2 undistorted = camera.Project(point_ref);
  const Vec2 raw = camera.Distort(undistorted);
  const int u = static_cast<int>(std::lround(raw.x())), v = static_cast<int>(std::lround(raw.y()));
  constexpr int kStep = 2;
  if (u < kStep || v < kStep || u >= depth_m.cols - kStep || v >= depth_m.rows - kStep) return std::nullopt;
  if (!mask.empty() && mask.at<std::uint8_t>(v, u) != 0) return std::nullopt;
  const double d = depth_m.at<float>(v, u);
  if (!(d >= options.min_depth_m && d <= options.max_depth_m)) return std::nullopt;
  // The normal's direction only: raw pixels back-projected without the distortion model.
  Vec3 neighbour[4];
  const int du[4] = {kStep, -kStep, 0, 0}, dv[4] = {0, 0, kStep, -kStep};
  for (int k = 0; k < 4; ++k) {
    const double dk = depth_m.at<float>(v + dv[k], u + du[k]);
    if (!(dk > 0) || std::abs(dk - d) > options.same_surface_ratio * d) return std::nullopt;
    neighbour[k] = camera.Backproject(Vec2(u + du[k], v + dv[k]), dk);
  }
  Vec3 normal = (neighbour[0] - neighbour[1]).cross(neighbour[2] - neighbour[3]);
  if (!(normal.norm() > 0)) return std::nullopt;
  normal.normalize();
  if (normal.dot(point_ref) > 0) normal = -normal;
  // The reading's own pixel, undistorted to first order (the distortion is locally a shift).
  const Vec2 pixel = undistorted + Vec2(u - raw.x(), v - raw.y());
  return SurfaceHit{d, camera.Backproject(pixel, d), normal};
}

struct Linearisation {
  Mat6 h = Mat6::Zero();
  Vec6 b = Vec6::Zero();  // -J^T W r
  int samples = 0;
};

Linearisation Linearise(const PinholeCamera& camera, const std::vector<Sample>& samples, const cv::Mat& reference_depth_m,
                        const cv::Mat& reference_mask, const Rigid3& reference_from_cam, const DepthAlignmentOptions& options) {
  Linearisation out;
  const Mat3 rotation = reference_from_cam.rotation_matrix();
  for (const Sample& sample : samples) {
    const Vec3 point_ref = reference_from_cam * sample.point_cam;
    const std::optional<SurfaceHit> hit = ReferenceSurface(camera, reference_depth_m, reference_mask, point_ref, options);
    if (!hit) continue;
    const double sigma_ref = options.depth_noise_at_1m * hit->depth * hit->depth;
    const double sigma = std::sqrt(sample.sigma2 + sigma_ref * sigma_ref);
    const double residual = hit->normal.dot(point_ref - hit->point) / sigma;
    if (std::abs(residual) > options.gate_sigmas) continue;
    // d(point_ref)/d(rho, phi) = R_ref_from_cam [-I, [p_cam]x] (the left perturbation of cam_from_world).
    Eigen::Matrix<double, 1, 6> jacobian;
    const Eigen::RowVector3d n_rotated = hit->normal.transpose() * rotation;
    jacobian << -n_rotated, n_rotated * Skew(sample.point_cam);
    jacobian /= sigma;
    const double weight = std::abs(residual) <= 1.0 ? 1.0 : 1.0 / std::abs(residual);  // Huber at 1 sigma
    out.h.noalias() += weight * jacobian.transpose() * jacobian;
    out.b.noalias() -= weight * jacobian.transpose() * residual;
    ++out.samples;
  }
  return out;
}

Rigid3 ApplyLeft(const Vec6& step, const Rigid3& cam_from_world) {
  const Mat3 rotation = ExpSO3(step.tail<3>());
  return Rigid3(Mat3(rotation * cam_from_world.rotation_matrix()), Vec3(rotation * cam_from_world.translation() + step.head<3>()));
}

}  // namespace

DepthAligner::DepthAligner(const PinholeCamera& camera, const DepthAlignmentOptions& options)
    : camera_(camera), options_(options) {
  options_.Check();
  const int stride = options_.sample_stride_px, first = stride / 2;
  const int rows = (camera.height() - first + stride - 1) / stride, cols = (camera.width() - first + stride - 1) / stride;
  std::vector<cv::Point2f> raw;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) raw.emplace_back(static_cast<float>(first + c * stride), static_cast<float>(first + r * stride));
  const std::vector<cv::Point2f> undistorted = camera.Undistort(raw);
  ray_x_.create(rows, cols, CV_64F);
  ray_y_.create(rows, cols, CV_64F);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const cv::Point2f& p = undistorted[static_cast<std::size_t>(r) * cols + c];
      ray_x_.at<double>(r, c) = (p.x - camera.cx()) / camera.fx();
      ray_y_.at<double>(r, c) = (p.y - camera.cy()) / camera.fy();
    }
}

std::optional<DepthAlignment> DepthAligner::Align(const cv::Mat& depth_m, const cv::Mat& dynamic_mask,
                                                  const cv::Mat& reference_depth_m, const cv::Mat& reference_dynamic_mask,
                                                  const Rigid3& reference_cam_from_world,
                                                  const Rigid3& initial_cam_from_world) const {
  if (depth_m.type() != CV_32F || reference_depth_m.type() != CV_32F || depth_m.size() != reference_depth_m.size() ||
      depth_m.cols != camera_.width() || depth_m.rows != camera_.height())
    throw Error("depth alignment: depths must be CV_32F images of the camera's size");
  // Static samples: the grid pixels with a reading in range, off the mask, in the camera frame.
  std::vector<Sample> samples;
  const int stride = options_.sample_stride_px, first = stride / 2;
  for (int r = 0; r < ray_x_.rows; ++r)
    for (int c = 0; c < ray_x_.cols; ++c) {
      const int u = first + c * stride, v = first + r * stride;
      const double z = depth_m.at<float>(v, u);
      if (!(z >= options_.min_depth_m && z <= options_.max_depth_m)) continue;
      if (!dynamic_mask.empty() && dynamic_mask.at<std::uint8_t>(v, u) != 0) continue;
      const double sigma = options_.depth_noise_at_1m * z * z;
      samples.push_back({Vec3(ray_x_.at<double>(r, c) * z, ray_y_.at<double>(r, c) * z, z), sigma * sigma});
    }
  DepthAlignment result;
  result.cam_from_world = initial_cam_from_world;
  for (int iteration = 0; iteration < options_.iterations; ++iteration) {
    const Linearisation lin = Linearise(camera_, samples, reference_depth_m, reference_dynamic_mask,
                                        reference_cam_from_world * result.cam_from_world.inverse(), options_);
    result.information = lin.h;
    result.samples = lin.samples;
    if (lin.samples < options_.min_samples) return std::nullopt;
    // Directions the surfaces leave free get no step (damped by a fraction of the largest curvature).
    Mat6 damped = lin.h;
    damped.diagonal().array() += 1e-6 * lin.h.diagonal().maxCoeff();
    const Vec6 step = damped.ldlt().solve(lin.b);
    if (!step.allFinite()) return std::nullopt;
    result.cam_from_world = ApplyLeft(step, result.cam_from_world);
    if (step.head<3>().norm() < 1e-5 && step.tail<3>().norm() < 1e-5) break;  // 10 um, 10 urad
  }
  return result;
}

std::optional<DepthAlignment> AlignDepth(const PinholeCamera& camera, const cv::Mat& depth_m, const cv::Mat& dynamic_mask,
                                         const cv::Mat& reference_depth_m, const cv::Mat& reference_dynamic_mask,
                                         const Rigid3& reference_cam_from_world, const Rigid3& initial_cam_from_world,
                                         const DepthAlignmentOptions& options) {
  return DepthAligner(camera, options)
      .Align(depth_m, dynamic_mask, reference_depth_m, reference_dynamic_mask, reference_cam_from_world,
             initial_cam_from_world);
}

}  // namespace esdslam
