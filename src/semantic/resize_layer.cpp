#include "semantic/resize_layer.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <opencv2/dnn/all_layers.hpp>
#include <opencv2/dnn/layer.hpp>

#include "semantic/own_layer.h"

namespace esdslam {
namespace {

// Per output index along one axis: the two input indices blended and the weight of the second.
// Invariants: 0 <= first <= second <= in - 1, second <= first + 1, 0 <= weight < 1 (up to float
// rounding), weight 0 where second == first.
struct AxisTaps {
  std::vector<int> first, second;
  std::vector<float> weight;
};

// OpenCV's ResizeLayer::finalize: input pixels per output pixel, in float.
float AxisScale(int in, int out, bool align_corners) {
  if (align_corners && out > 1) return static_cast<float>(in - 1) / static_cast<float>(out - 1);
  return static_cast<float>(in) / static_cast<float>(out);
}

// The taps of OpenCV's bilinear loop: position i * scale in float, truncated to the first index.
AxisTaps Taps(int in, int out, bool align_corners) {
  const float scale = AxisScale(in, out, align_corners);
  AxisTaps taps;
  const auto n = static_cast<std::size_t>(out);
  taps.first.resize(n);
  taps.second.resize(n);
  taps.weight.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const float position = static_cast<float>(i) * scale;  // input pixels, >= 0
    const int first = static_cast<int>(position);
    // A position past the last input pixel (float rounding only) clamps to it with weight 0.
    taps.first[i] = std::min(first, in - 1);
    taps.second[i] = std::min(first + 1, in - 1);
    taps.weight[i] = taps.second[i] > taps.first[i] ? position - static_cast<float>(first) : 0.0f;
  }
  return taps;
}

// True when the (h, w) plane of every (n, c) of a 4-D CV_32F blob is one contiguous run of floats.
bool PlanesContiguous(const cv::Mat& blob) {
  return blob.dims == 4 && blob.type() == CV_32F && blob.step[3] == sizeof(float) &&
         blob.step[2] == static_cast<std::size_t>(blob.size[3]) * sizeof(float);
}

class SeparableResizeLayer final : public OwnLayer {
 public:
  explicit SeparableResizeLayer(const cv::dnn::LayerParams& params)
      : out_height_(params.get<int>("height")),
        out_width_(params.get<int>("width")),
        align_corners_(params.get<bool>("align_corners", false)) {
    setParamsFrom(params);
  }

  using cv::dnn::Layer::finalize;

  // One input N x C x h x w (the ONNX importer gives a Resize one: its scales or sizes are
  // constants it folds into the params) -> N x C x height x width. True (may run in place) when
  // that is h x w.
  bool getMemoryShapes(const std::vector<cv::dnn::MatShape>& inputs, const int /*required_outputs*/,
                       std::vector<cv::dnn::MatShape>& outputs,
                       std::vector<cv::dnn::MatShape>& /*internals*/) const override {
    CV_CheckEQ(inputs.size(), std::size_t{1}, "the separable Resize takes one input (no output-size blob)");
    CV_CheckEQ(inputs[0].size(), std::size_t{4}, "the separable Resize takes an N x C x H x W blob");
    outputs.assign(1, inputs[0]);
    outputs[0][2] = out_height_;
    outputs[0][3] = out_width_;
    return outputs[0][2] == inputs[0][2] && outputs[0][3] == inputs[0][3];
  }

  // The taps for the blob sizes the net settled on (called again when the net is reshaped).
  void finalize(cv::InputArrayOfArrays inputs_arr, cv::OutputArrayOfArrays outputs_arr) override {
    std::vector<cv::Mat> inputs, outputs;
    inputs_arr.getMatVector(inputs);
    outputs_arr.getMatVector(outputs);
    CV_Assert(inputs.size() == 1 && inputs[0].dims == 4 && outputs.size() == 1 && outputs[0].dims == 4);
    rows_ = Taps(inputs[0].size[2], outputs[0].size[2], align_corners_);
    cols_ = Taps(inputs[0].size[3], outputs[0].size[3], align_corners_);
    rows_read_.assign(static_cast<std::size_t>(inputs[0].size[2]), 0);
    for (std::size_t y = 0; y < rows_.first.size(); ++y)
      rows_read_[static_cast<std::size_t>(rows_.first[y])] = rows_read_[static_cast<std::size_t>(rows_.second[y])] = 1;
  }

  void ForwardMats(const std::vector<cv::Mat>& inputs, std::vector<cv::Mat>& outputs) override {
    const cv::Mat& in = inputs[0];
    cv::Mat& out = outputs[0];
    if (in.size[2] == out.size[2] && in.size[3] == out.size[3]) {  // same size: a copy, or nothing in place
      if (in.data != out.data) in.copyTo(out);
      return;
    }
    CV_CheckTypeEQ(in.type(), CV_32F, "the separable Resize computes float blobs");
    CV_Assert(PlanesContiguous(in) && PlanesContiguous(out) && in.size[0] == out.size[0] && in.size[1] == out.size[1]);
    CV_Assert(rows_.first.size() == static_cast<std::size_t>(out.size[2]) &&
              cols_.first.size() == static_cast<std::size_t>(out.size[3]) &&
              rows_read_.size() == static_cast<std::size_t>(in.size[2]));
    // The planes in one stripe per OpenCV thread (one stripe, run here, with cv::setNumThreads(1)).
    const int channels = in.size[1];
    cv::parallel_for_(cv::Range(0, in.size[0] * channels), [&](const cv::Range& planes) {
      // Input rows resized to the output width (in rows x out cols).
      std::vector<float> row_buffer(static_cast<std::size_t>(in.size[2]) * static_cast<std::size_t>(out.size[3]));
      for (int p = planes.start; p < planes.end; ++p)
        ResizePlane(in.ptr<float>(p / channels, p % channels), in.size[2], in.size[3],
                    out.ptr<float>(p / channels, p % channels), row_buffer.data());
    }, cv::getNumThreads());
  }

 private:
  // One plane: in (in_rows x in_cols, contiguous) -> out (rows_ x cols_ taps, contiguous).
  // row_buffer holds in_rows x out_cols floats.
  void ResizePlane(const float* in, int in_rows, int in_cols, float* out, float* row_buffer) const {
    const std::size_t out_cols = cols_.first.size();
    const int* first = cols_.first.data();
    const int* second = cols_.second.data();
    const float* weight = cols_.weight.data();
    for (int r = 0; r < in_rows; ++r) {
      if (!rows_read_[static_cast<std::size_t>(r)]) continue;  // no output row reads it
      const float* src = in + static_cast<std::ptrdiff_t>(r) * in_cols;
      float* dst = row_buffer + static_cast<std::size_t>(r) * out_cols;
      for (std::size_t x = 0; x < out_cols; ++x) {
        const float a = src[first[x]];
        dst[x] = a + weight[x] * (src[second[x]] - a);
      }
    }
    for (std::size_t y = 0; y < rows_.first.size(); ++y) {
      const float* a = row_buffer + static_cast<std::size_t>(rows_.first[y]) * out_cols;
      const float* b = row_buffer + static_cast<std::size_t>(rows_.second[y]) * out_cols;
      const float w = rows_.weight[y];
      float* dst = out + y * out_cols;
      for (std::size_t x = 0; x < out_cols; ++x) dst[x] = a[x] + w * (b[x] - a[x]);
    }
  }

  int out_height_, out_width_;  // px, from the params (> 0)
  bool align_corners_;
  AxisTaps rows_, cols_;  // set by finalize: output rows / columns to input ones
  std::vector<char> rows_read_;  // per input row: 1 when some output row reads it (finalize)
};

// A positive whole number of pixels.
bool IsPixelCount(const cv::dnn::LayerParams& params, const std::string& key) {
  if (!params.has(key)) return false;
  const double value = params.get<double>(key);
  return value >= 1.0 && value == std::floor(value) && value < 1e6;
}

}  // namespace

bool SeparableResizeHandles(const cv::dnn::LayerParams& params) {
  if (params.get<cv::String>("interpolation", "") != "bilinear") return false;
  if (params.get<bool>("half_pixel_centers", false)) return false;
  if (params.has("zoom_factor") || params.has("zoom_factor_x") || params.has("zoom_factor_y")) return false;
  if (!IsPixelCount(params, "width") || !IsPixelCount(params, "height")) return false;
  // The importer's coordinate mode, where given, must be the one align_corners stands for.
  const bool align_corners = params.get<bool>("align_corners", false);
  if (!params.has("coordinate_transformation_mode")) return true;
  const std::string mode = params.get<cv::String>("coordinate_transformation_mode");
  return mode == (align_corners ? "align_corners" : "asymmetric");
}

cv::Ptr<cv::dnn::Layer> CreateResizeLayer(cv::dnn::LayerParams& params) {
  if (SeparableResizeHandles(params)) return cv::makePtr<SeparableResizeLayer>(params);
  return cv::dnn::ResizeLayer::create(params);
}

bool IsSeparableResize(const cv::dnn::Layer& layer) {
  return dynamic_cast<const SeparableResizeLayer*>(&layer) != nullptr;
}

}  // namespace esdslam
