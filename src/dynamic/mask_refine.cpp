#include "dynamic/mask_refine.h"

#include <algorithm>
#include <cstring>
#include <vector>

#include "common/error.h"
#include "common/setting_error.h"

namespace esdslam {
namespace {

cv::Size Reduced(cv::Size size, int factor) {
  return {(size.width + factor - 1) / factor, (size.height + factor - 1) / factor};
}

void RequireFactor(int factor, const char* what) {
  if (factor < 1) throw Error(fmt::format("{}: factor must be >= 1, got {}", what, factor));
}

}  // namespace

void MaskRefineOptions::Check() const {
  CheckRange("Dynamic.maskDilation", dilation_px, 0, 200, "px");
  CheckRange("Dynamic.refineScale", scale, 1, 4);
}

cv::Mat ReduceMaskAny(const cv::Mat& mask, int factor) {
  RequireFactor(factor, "ReduceMaskAny");
  if (mask.type() != CV_8UC1) throw Error("ReduceMaskAny: expected a CV_8UC1 mask");
  if (factor == 1) return mask;
  // Rows of a block OR-ed together, then each run of `factor` bytes: branch-free inner loops.
  cv::Mat small(Reduced(mask.size(), factor), CV_8U);
  std::vector<std::uint8_t> any_row(static_cast<std::size_t>(mask.cols));
  for (int y = 0; y < small.rows; ++y) {
    std::fill(any_row.begin(), any_row.end(), 0);
    for (int v = y * factor; v < std::min(mask.rows, (y + 1) * factor); ++v) {
      const std::uint8_t* in = mask.ptr<std::uint8_t>(v);
      for (int u = 0; u < mask.cols; ++u) any_row[static_cast<std::size_t>(u)] |= in[u];
    }
    std::uint8_t* out = small.ptr<std::uint8_t>(y);
    for (int x = 0; x < small.cols; ++x) {
      std::uint8_t any = 0;
      for (int u = x * factor; u < std::min(mask.cols, (x + 1) * factor); ++u) any |= any_row[static_cast<std::size_t>(u)];
      out[x] = any ? 255 : 0;
    }
  }
  return small;
}

cv::Mat SubsampleDepth(const cv::Mat& depth_m, int factor) {
  RequireFactor(factor, "SubsampleDepth");
  if (depth_m.type() != CV_32FC1) throw Error("SubsampleDepth: expected a CV_32FC1 depth image");
  if (factor == 1) return depth_m;
  cv::Mat small(Reduced(depth_m.size(), factor), CV_32F);
  for (int y = 0; y < small.rows; ++y) {
    const float* in = depth_m.ptr<float>(y * factor);
    float* out = small.ptr<float>(y);
    for (int x = 0; x < small.cols; ++x) out[x] = in[x * factor];
  }
  return small;
}

namespace {

// row[u] = in[u / kFactor] for u in [0, width).
template <int kFactor>
void EnlargeRow(const std::uint8_t* in, std::uint8_t* row, int width) {
  const int whole = width / kFactor;  // source pixels whose run fits entirely
  for (int x = 0; x < whole; ++x)
    for (int k = 0; k < kFactor; ++k) row[x * kFactor + k] = in[x];
  for (int u = whole * kFactor; u < width; ++u) row[u] = in[whole];
}

}  // namespace

cv::Mat EnlargeNearest(const cv::Mat& small, int factor, cv::Size size) {
  RequireFactor(factor, "EnlargeNearest");
  if (small.type() != CV_8UC1) throw Error("EnlargeNearest: expected a CV_8UC1 image");
  const cv::Size needed = Reduced(size, factor);
  if (small.cols < needed.width || small.rows < needed.height)
    throw Error(fmt::format("EnlargeNearest: {}x{} pixels cannot cover {}x{} at factor {}", small.cols, small.rows,
                            size.width, size.height, factor));
  if (factor == 1 && small.size() == size) return small;
  cv::Mat out(size, CV_8U);
  for (int v = 0; v < size.height; v += factor) {
    const std::uint8_t* in = small.ptr<std::uint8_t>(v / factor);
    std::uint8_t* row = out.ptr<std::uint8_t>(v);
    // The first row of the block; the usual factors with a constant run length, no division per pixel.
    if (factor == 2) {
      EnlargeRow<2>(in, row, size.width);
    } else if (factor == 4) {
      EnlargeRow<4>(in, row, size.width);
    } else {
      for (int u = 0; u < size.width; ++u) row[u] = in[u / factor];
    }
    for (int k = 1; k < factor && v + k < size.height; ++k)
      std::memcpy(out.ptr<std::uint8_t>(v + k), row, static_cast<std::size_t>(size.width));
  }
  return out;
}

}  // namespace esdslam
