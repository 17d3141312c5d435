#include "semantic/score_upsampling.h"

#include <algorithm>

#include "common/error.h"

namespace esdslam {
namespace {

// Per output index along one axis: the first input index and the weight of the next one.
struct AxisTaps {
  std::vector<int> first;
  std::vector<float> next_weight;
};

AxisTaps AlignCornersTaps(int in, int out) {
  AxisTaps taps;
  taps.first.resize(static_cast<std::size_t>(out));
  taps.next_weight.resize(static_cast<std::size_t>(out));
  const double scale = out > 1 ? static_cast<double>(in - 1) / (out - 1) : 0.0;
  for (int i = 0; i < out; ++i) {
    const double source = i * scale;
    const int first = std::min(static_cast<int>(source), in - 1);
    taps.first[static_cast<std::size_t>(i)] = first;
    // At the last input index the next one is itself (weight 0 of a clamped neighbour).
    taps.next_weight[static_cast<std::size_t>(i)] = first + 1 < in ? static_cast<float>(source - first) : 0.0f;
  }
  return taps;
}

// One class plane: the rows first (each input row to out width), then each output row from two.
cv::Mat UpsamplePlane(const float* in, int in_rows, int in_cols, const AxisTaps& cols, const AxisTaps& rows,
                      cv::Mat& row_buffer) {
  const int out_cols = static_cast<int>(cols.first.size());
  for (int r = 0; r < in_rows; ++r) {
    const float* src = in + static_cast<std::ptrdiff_t>(r) * in_cols;
    float* dst = row_buffer.ptr<float>(r);
    for (int x = 0; x < out_cols; ++x) {
      const int c = cols.first[static_cast<std::size_t>(x)];
      const float w = cols.next_weight[static_cast<std::size_t>(x)];
      const float a = src[c], b = src[std::min(c + 1, in_cols - 1)];
      dst[x] = a + w * (b - a);
    }
  }
  cv::Mat plane(static_cast<int>(rows.first.size()), out_cols, CV_32F);
  for (int y = 0; y < plane.rows; ++y) {
    const int r = rows.first[static_cast<std::size_t>(y)];
    const float w = rows.next_weight[static_cast<std::size_t>(y)];
    const float* a = row_buffer.ptr<float>(r);
    const float* b = row_buffer.ptr<float>(std::min(r + 1, in_rows - 1));
    float* dst = plane.ptr<float>(y);
    for (int x = 0; x < out_cols; ++x) dst[x] = a[x] + w * (b[x] - a[x]);
  }
  return plane;
}

}  // namespace

std::vector<cv::Mat> UpsampleAlignCorners(const cv::Mat& scores, cv::Size out_size) {
  if (scores.type() != CV_32F || scores.dims != 4 || scores.size[0] != 1 || !scores.isContinuous())
    throw Error("UpsampleAlignCorners: expected a contiguous CV_32F blob 1 x C x h x w");
  if (out_size.width <= 0 || out_size.height <= 0) throw Error("UpsampleAlignCorners: empty output size");
  const int classes = scores.size[1], in_rows = scores.size[2], in_cols = scores.size[3];
  const AxisTaps cols = AlignCornersTaps(in_cols, out_size.width);
  const AxisTaps rows = AlignCornersTaps(in_rows, out_size.height);
  cv::Mat row_buffer(in_rows, out_size.width, CV_32F);
  std::vector<cv::Mat> planes;
  planes.reserve(static_cast<std::size_t>(classes));
  for (int c = 0; c < classes; ++c)
    planes.push_back(UpsamplePlane(scores.ptr<float>(0, c), in_rows, in_cols, cols, rows, row_buffer));
  return planes;
}

}  // namespace esdslam
