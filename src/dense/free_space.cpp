#include "dense/free_space.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "common/error.h"

namespace esdslam {

FreeSpaceView::FreeSpaceView(const PinholeCamera& camera, const Rigid3& world_from_cam, const cv::Mat& depth_m, int stride,
                             const DenseOptions& options)
    : intrinsics_(camera.intrinsics()),
      distorted_(camera.intrinsics().HasDistortion()),
      inv_stride_(1.0f / static_cast<float>(stride)),
      noise_at_1m_(static_cast<float>(options.depth_noise_at_1m)),
      sigmas_(static_cast<float>(options.free_space_sigmas)),
      min_margin_(static_cast<float>(options.free_space_min_margin)) {
  if (depth_m.type() != CV_32F || stride < 1) throw Error("free space: depth must be CV_32F, stride >= 1");
  const Rigid3 cam_from_world = world_from_cam.inverse();
  rotation_ = cam_from_world.rotation_matrix().cast<float>();
  translation_ = cam_from_world.translation().cast<float>();
  // Readings beyond Dense.maxDepth give no points but still prove the space in front of them
  // free (their margin grows with sigma(d)).
  cv::Mat valid_or_zero = depth_m.clone();
  cv::patchNaNs(valid_or_zero, 0.0);
  valid_or_zero.setTo(0.0f, valid_or_zero < 0);
  depth_ = valid_or_zero;
  // The window is in raw pixels: a coarser sample grid uses proportionally fewer samples.
  const int samples = options.free_space_window_px > 0 ? std::max(1, static_cast<int>(std::lround(options.free_space_window_px * inv_stride_))) : 0;
  const int k = 2 * samples + 1;
  cv::erode(valid_or_zero, min_depth_, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(k, k)), cv::Point(-1, -1), 1,
            cv::BORDER_CONSTANT, cv::Scalar(0.0));
}

float FreeSpaceView::Margin(float depth) const { return std::max(min_margin_, sigmas_ * noise_at_1m_ * depth * depth); }

FreeSpaceVerdict FreeSpaceView::ClassifyInCamera(const Eigen::Vector3f& p, float extent) const {
  if (!(p.z() > 0.05f)) return FreeSpaceVerdict::kUnknown;
  float x = p.x() / p.z(), y = p.y() / p.z();
  if (distorted_) {
    const CameraIntrinsics& k = intrinsics_;
    const float r2 = x * x + y * y;
    const float radial = 1.0f + static_cast<float>(k.k1) * r2 + static_cast<float>(k.k2) * r2 * r2 + static_cast<float>(k.k3) * r2 * r2 * r2;
    const float xd = x * radial + 2.0f * static_cast<float>(k.p1) * x * y + static_cast<float>(k.p2) * (r2 + 2.0f * x * x);
    const float yd = y * radial + static_cast<float>(k.p1) * (r2 + 2.0f * y * y) + 2.0f * static_cast<float>(k.p2) * x * y;
    x = xd;
    y = yd;
  }
  const float u = static_cast<float>(intrinsics_.fx) * x + static_cast<float>(intrinsics_.cx);
  const float v = static_cast<float>(intrinsics_.fy) * y + static_cast<float>(intrinsics_.cy);
  const float column = u * inv_stride_ + 0.5f, row = v * inv_stride_ + 0.5f;  // nearest sample
  if (!(column >= 0 && row >= 0 && column < depth_.cols && row < depth_.rows)) return FreeSpaceVerdict::kUnknown;
  const int c = static_cast<int>(column), r = static_cast<int>(row);
  const float d = depth_.at<float>(r, c);
  if (!std::isfinite(d) || !(d > 0)) return FreeSpaceVerdict::kUnknown;
  const float margin = Margin(d) + extent;
  if (std::abs(d - p.z()) <= margin) return FreeSpaceVerdict::kSeen;
  const float d_min = min_depth_.at<float>(r, c);
  if (d_min > 0 && d_min > p.z() + Margin(d_min) + extent) return FreeSpaceVerdict::kFree;
  return FreeSpaceVerdict::kUnknown;
}

}  // namespace esdslam
