#include "dynamic/mask_dilation.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <vector>

#include <opencv2/imgproc.hpp>

namespace esdslam {
namespace {

// Half-width of each row of OpenCV's elliptic kernel of radius r (index dy + r); -1: empty row.
std::vector<int> EllipseRowHalfWidths(int radius_px) {
  const cv::Mat kernel =
      cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * radius_px + 1, 2 * radius_px + 1));
  std::vector<int> half_widths(kernel.rows, -1);
  for (int row = 0; row < kernel.rows; ++row) {
    const std::uint8_t* k = kernel.ptr<std::uint8_t>(row);
    for (int col = 0; col <= radius_px; ++col)
      if (k[col]) {
        half_widths[row] = radius_px - col;  // the run is centred: [r - a, r + a]
        break;
      }
  }
  return half_widths;
}

cv::Mat DilateRowsByRuns(const cv::Mat& mask, int radius_px) {
  const std::vector<int> half_widths = EllipseRowHalfWidths(radius_px);
  std::map<int, cv::Mat> horizontal;  // half-width -> mask dilated horizontally by it
  for (const int a : half_widths) {
    if (a < 0 || horizontal.count(a)) continue;
    cv::Mat& h = horizontal[a];
    if (a == 0) h = mask;
    else cv::dilate(mask, h, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * a + 1, 1)));
  }
  // The horizontal dilation each kernel row takes (null: empty row), looked up once, not per row.
  std::vector<const cv::Mat*> row_source(half_widths.size(), nullptr);
  for (std::size_t i = 0; i < half_widths.size(); ++i)
    if (half_widths[i] >= 0) row_source[i] = &horizontal.at(half_widths[i]);
  cv::Mat out = cv::Mat::zeros(mask.size(), CV_8U);
  const int cols = mask.cols;
  for (int v = 0; v < mask.rows; ++v) {
    std::uint8_t* dst = out.ptr<std::uint8_t>(v);
    for (int dy = -radius_px; dy <= radius_px; ++dy) {
      const int src_row = v + dy;
      const cv::Mat* source = row_source[dy + radius_px];
      if (!source || src_row < 0 || src_row >= mask.rows) continue;
      const std::uint8_t* src = source->ptr<std::uint8_t>(src_row);
      for (int u = 0; u < cols; ++u) dst[u] = std::max(dst[u], src[u]);
    }
  }
  return out;
}

}  // namespace

cv::Mat DilateEllipse(const cv::Mat& mask, int radius_px) {
  if (radius_px <= 0 || mask.empty()) return mask;
  // Every offset inside the image lies within the ellipse (+2 px for the kernel's rounding).
  if (radius_px >= std::hypot(mask.cols, mask.rows) + 2) {
    double max_value = 0;
    cv::minMaxLoc(mask, nullptr, &max_value);
    return cv::Mat(mask.size(), mask.type(), cv::Scalar(max_value));
  }
  // Below this radius OpenCV's kernel is as fast (measured at 640x480: r 3 0.45 ms against 0.63).
  constexpr int kRowRunsFromRadius = 6;
  if (mask.type() == CV_8U && radius_px >= kRowRunsFromRadius) return DilateRowsByRuns(mask, radius_px);
  cv::Mat out;
  cv::dilate(mask, out, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * radius_px + 1, 2 * radius_px + 1)));
  return out;
}

}  // namespace esdslam
