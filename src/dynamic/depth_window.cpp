#include "dynamic/depth_window.h"

#include <algorithm>
#include <limits>

#include <opencv2/imgproc.hpp>

#include "common/error.h"

namespace esdslam {

DepthWindow::DepthWindow(const cv::Mat& depth_m, int radius_px) : depth_m_(depth_m), radius_(radius_px) {
  if (depth_m.type() != CV_32F || radius_px < 0) throw Error("DepthWindow: need CV_32F depth and radius >= 0");
  if (radius_px <= kDirectRadius) return;
  const int cols = (depth_m.cols + kBlock - 1) / kBlock, rows = (depth_m.rows + kBlock - 1) / kBlock;
  const float inf = std::numeric_limits<float>::infinity();
  cv::Mat block_near(rows, cols, CV_32F, cv::Scalar(inf)), block_far(rows, cols, CV_32F, cv::Scalar(0));
  for (int v = 0; v < depth_m.rows; ++v) {
    const float* row = depth_m.ptr<float>(v);
    float* near = block_near.ptr<float>(v / kBlock);
    float* far = block_far.ptr<float>(v / kBlock);
    for (int u = 0; u < depth_m.cols; ++u) {
      if (!(row[u] > 0)) continue;
      near[u / kBlock] = std::min(near[u / kBlock], row[u]);
      far[u / kBlock] = std::max(far[u / kBlock], row[u]);
    }
  }
  const int k = (radius_px + kBlock - 1) / kBlock;
  const cv::Mat kernel = cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * k + 1, 2 * k + 1));
  cv::erode(block_near, block_near_, kernel, cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, cv::Scalar(inf));
  cv::dilate(block_far, block_far_, kernel, cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, cv::Scalar(0));
}

bool DepthWindow::Range(const cv::Point& pixel, float* near, float* far) const {
  if (radius_ > kDirectRadius) {
    const cv::Point block(std::clamp(pixel.x / kBlock, 0, block_near_.cols - 1),
                          std::clamp(pixel.y / kBlock, 0, block_near_.rows - 1));
    *near = block_near_.at<float>(block);
    *far = block_far_.at<float>(block);
    return *far > 0;
  }
  *near = std::numeric_limits<float>::infinity();
  *far = 0.f;
  for (int v = std::max(0, pixel.y - radius_); v <= std::min(depth_m_.rows - 1, pixel.y + radius_); ++v) {
    const float* row = depth_m_.ptr<float>(v);
    for (int u = std::max(0, pixel.x - radius_); u <= std::min(depth_m_.cols - 1, pixel.x + radius_); ++u) {
      if (!(row[u] > 0)) continue;
      *near = std::min(*near, row[u]);
      *far = std::max(*far, row[u]);
    }
  }
  return *far > 0;
}

}  // namespace esdslam
