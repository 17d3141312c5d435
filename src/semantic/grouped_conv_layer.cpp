#include "semantic/grouped_conv_layer.h"

#include <algorithm>
#include <cstddef>
#include <optional>
#include <vector>

#include <opencv2/dnn/all_layers.hpp>
#include <opencv2/dnn/layer.hpp>

#include "semantic/conv_kernels.h"
#include "semantic/own_layer.h"

namespace esdslam {
namespace {

// Floats of sums per block of output rows in the stride-1 path (16 KiB: half an L1 data cache).
constexpr int kRowBlockFloats = 4096;

// The geometry of a 2-D convolution with explicit pads, from OpenCV's own parsing of the params.
struct ConvGeometry {
  int kernel_h = 0, kernel_w = 0;    // taps
  int stride_h = 1, stride_w = 1;    // input px per output px
  int dilation_h = 1, dilation_w = 1;  // input px between taps
  int pad_top = 0, pad_left = 0, pad_bottom = 0, pad_right = 0;  // zero rows / columns added
};

// OpenCV's parsing of `params` (it builds its convolution layer to read them); nothing when
// OpenCV rejects them (e.g. pads differing per side: its layer says why), they are not 2-D, or
// they give a pad mode ("SAME"/"VALID") instead of pads.
std::optional<ConvGeometry> ParsedGeometry(const cv::dnn::LayerParams& params) {
  cv::Ptr<cv::dnn::BaseConvolutionLayer> parsed;
  try {
    parsed = cv::dnn::ConvolutionLayer::create(params);
  } catch (const cv::Exception&) {
    return std::nullopt;
  }
  if (parsed->kernel_size.size() != 2 || parsed->strides.size() != 2 || parsed->dilations.size() != 2 ||
      parsed->pads_begin.size() != 2 || parsed->pads_end.size() != 2 || !parsed->padMode.empty())
    return std::nullopt;
  ConvGeometry g;
  g.kernel_h = static_cast<int>(parsed->kernel_size[0]);
  g.kernel_w = static_cast<int>(parsed->kernel_size[1]);
  g.stride_h = static_cast<int>(parsed->strides[0]);
  g.stride_w = static_cast<int>(parsed->strides[1]);
  g.dilation_h = static_cast<int>(parsed->dilations[0]);
  g.dilation_w = static_cast<int>(parsed->dilations[1]);
  g.pad_top = static_cast<int>(parsed->pads_begin[0]);
  g.pad_left = static_cast<int>(parsed->pads_begin[1]);
  g.pad_bottom = static_cast<int>(parsed->pads_end[0]);
  g.pad_right = static_cast<int>(parsed->pads_end[1]);
  return g;
}

// Output size along one axis (OpenCV's and ONNX's formula); <= 0 when the kernel does not fit.
int OutputSize(int in, int pad_begin, int pad_end, int kernel, int stride, int dilation) {
  return (in + pad_begin + pad_end - dilation * (kernel - 1) - 1) / stride + 1;
}

// out[x] += weight * in[x * stride + offset] for x in [0, out_cols) where the input index is in
// [0, in_cols); the rest is zero padding and adds nothing.
void AddTapRow(const ConvKernels& kernels, const float* in, int in_cols, float weight, int offset, int stride,
               float* out, int out_cols) {
  // First x with x * stride + offset >= 0, and one past the last with it < in_cols.
  const int begin = offset >= 0 ? 0 : (-offset + stride - 1) / stride;
  const int end = std::min(out_cols, in_cols - offset <= 0 ? 0 : (in_cols - offset - 1) / stride + 1);
  if (stride == 1) {
    if (end > begin)
      kernels.multiply_add(in + offset + begin, weight, out + begin, static_cast<std::size_t>(end - begin));
  } else if (stride == 2) {
    kernels.add_stride2_tap_row(in, weight, offset, out, begin, end);
  } else {
    for (int x = begin; x < end; ++x) out[x] += weight * in[x * stride + offset];
  }
}

class GroupedConvolutionLayer final : public OwnLayer {
 public:
  GroupedConvolutionLayer(const cv::dnn::LayerParams& params, const ConvGeometry& geometry, const ConvKernels& kernels)
      : kernels_(kernels), geometry_(geometry), groups_(params.get<int>("group")) {
    setParamsFrom(params);
    weights_ = blobs[0];  // [out, in / group, kh, kw], checked by GroupedConvolutionHandles
    outputs_ = weights_.size[0];
    inputs_per_group_ = weights_.size[1];
    bias_.assign(static_cast<std::size_t>(outputs_), 0.0f);
    if (blobs.size() > 1) {
      const cv::Mat bias = blobs[1].reshape(1, 1);
      for (int c = 0; c < outputs_; ++c) bias_[static_cast<std::size_t>(c)] = bias.at<float>(c);
    }
  }

  bool getMemoryShapes(const std::vector<cv::dnn::MatShape>& inputs, const int /*required_outputs*/,
                       std::vector<cv::dnn::MatShape>& outputs,
                       std::vector<cv::dnn::MatShape>& /*internals*/) const override {
    CV_CheckEQ(inputs.size(), std::size_t{1}, "the grouped convolution takes one input (constant weights)");
    CV_CheckEQ(inputs[0].size(), std::size_t{4}, "the grouped convolution takes an N x C x H x W blob");
    CV_CheckEQ(inputs[0][1], groups_ * inputs_per_group_, "input channels do not match the weights");
    const ConvGeometry& g = geometry_;
    const int rows = OutputSize(inputs[0][2], g.pad_top, g.pad_bottom, g.kernel_h, g.stride_h, g.dilation_h);
    const int cols = OutputSize(inputs[0][3], g.pad_left, g.pad_right, g.kernel_w, g.stride_w, g.dilation_w);
    CV_Check(rows, rows > 0 && cols > 0, "the kernel does not fit the padded input");
    outputs.assign(1, cv::dnn::MatShape{inputs[0][0], outputs_, rows, cols});
    return false;
  }

  void ForwardMats(const std::vector<cv::Mat>& inputs, std::vector<cv::Mat>& outputs) override {
    const cv::Mat& in = inputs[0];
    cv::Mat& out = outputs[0];
    CV_CheckTypeEQ(in.type(), CV_32F, "the grouped convolution computes float blobs");
    CV_Assert(in.isContinuous() && out.isContinuous() && in.size[0] == out.size[0]);
    const int work = out.size[0] * groups_;
    cv::parallel_for_(cv::Range(0, work), [&](const cv::Range& range) {
      for (int w = range.start; w < range.end; ++w) OutputGroup(in, w / groups_, w % groups_, out);
    }, cv::getNumThreads());
  }

 private:
  // The output channels of group `group` of image `n`: every tap of the group's inputs, then the
  // bias (added last in both branches).
  void OutputGroup(const cv::Mat& in, int n, int group, cv::Mat& out) const {
    if (geometry_.stride_h == 1 && geometry_.stride_w == 1) {
      OutputGroupStride1(in, n, group, out);
      return;
    }
    const int outputs_per_group = outputs_ / groups_;
    const int first_input = group * inputs_per_group_;
    const std::ptrdiff_t plane_size = static_cast<std::ptrdiff_t>(out.size[2]) * out.size[3];
    for (int j = 0; j < outputs_per_group; ++j) {
      const int channel = group * outputs_per_group + j;
      float* out_plane = out.ptr<float>(n, channel);
      std::fill(out_plane, out_plane + plane_size, 0.0f);
      for (int i = 0; i < inputs_per_group_; ++i)
        AddStridedInput(in.ptr<float>(n, first_input + i), in.size[2], in.size[3], weights_.ptr<float>(channel, i),
                        out.size[2], out.size[3], out_plane);
      const float bias = bias_[static_cast<std::size_t>(channel)];
      for (std::ptrdiff_t k = 0; k < plane_size; ++k) out_plane[k] += bias;
    }
  }

  // Stride 1: each input plane is copied once into a zero-padded plane (padded_cols wide); the
  // outputs are accumulated as rows padded_cols wide (the columns past the output width hold sums
  // that wrap into the next row and are dropped), so that each tap is one multiply-add over a
  // block of rows (kRowBlockFloats floats: the block's sums stay in the L1 cache). The bias is
  // added as the sums are written out.
  void OutputGroupStride1(const cv::Mat& in, int n, int group, cv::Mat& out) const {
    const ConvGeometry& g = geometry_;
    const int in_rows = in.size[2], in_cols = in.size[3];
    const int out_rows = out.size[2], out_cols = out.size[3];
    const int outputs_per_group = outputs_ / groups_;
    const int padded_cols = in_cols + g.pad_left + g.pad_right;
    const int padded_rows = in_rows + g.pad_top + g.pad_bottom;
    const std::size_t plane_sums = static_cast<std::size_t>(out_rows) * static_cast<std::size_t>(padded_cols);
    // The last tap reads (kernel_w - 1) * dilation_w floats past the padded plane: zeros.
    const std::size_t padded_size = static_cast<std::size_t>(padded_rows) * static_cast<std::size_t>(padded_cols) +
                                    static_cast<std::size_t>((g.kernel_w - 1) * g.dilation_w);
    thread_local std::vector<float> padded, sums;
    padded.assign(padded_size, 0.0f);
    sums.assign(plane_sums * static_cast<std::size_t>(outputs_per_group), 0.0f);
    const int block_rows = std::max(1, kRowBlockFloats / padded_cols);
    for (int i = 0; i < inputs_per_group_; ++i) {
      const float* in_plane = in.ptr<float>(n, group * inputs_per_group_ + i);
      for (int y = 0; y < in_rows; ++y)
        std::copy(in_plane + static_cast<std::ptrdiff_t>(y) * in_cols, in_plane + static_cast<std::ptrdiff_t>(y + 1) * in_cols,
                  padded.data() + static_cast<std::ptrdiff_t>(y + g.pad_top) * padded_cols + g.pad_left);
      for (int j = 0; j < outputs_per_group; ++j) {
        const float* taps = weights_.ptr<float>(group * outputs_per_group + j, i);  // kernel_h x kernel_w
        float* channel_sums = sums.data() + plane_sums * static_cast<std::size_t>(j);
        for (int y0 = 0; y0 < out_rows; y0 += block_rows) {
          const std::ptrdiff_t first = static_cast<std::ptrdiff_t>(y0) * padded_cols;
          const std::size_t count = static_cast<std::size_t>(std::min(block_rows, out_rows - y0)) *
                                    static_cast<std::size_t>(padded_cols);
          if (g.kernel_h == 3 && g.kernel_w == 3) {  // every grouped conv of ESPNetv2
            kernels_.multiply_add_3x3(padded.data() + first,
                                      static_cast<std::ptrdiff_t>(g.dilation_h) * padded_cols, g.dilation_w, taps,
                                      channel_sums + first, count);
            continue;
          }
          for (int ky = 0; ky < g.kernel_h; ++ky)
            for (int kx = 0; kx < g.kernel_w; ++kx)
              kernels_.multiply_add(padded.data() + first +
                                        static_cast<std::ptrdiff_t>(ky * g.dilation_h) * padded_cols +
                                        kx * g.dilation_w,
                                    taps[ky * g.kernel_w + kx], channel_sums + first, count);
        }
      }
    }
    // The sums of the output columns, plus the bias.
    for (int j = 0; j < outputs_per_group; ++j) {
      const int channel = group * outputs_per_group + j;
      const float* channel_sums = sums.data() + plane_sums * static_cast<std::size_t>(j);
      float* out_plane = out.ptr<float>(n, channel);
      const float bias = bias_[static_cast<std::size_t>(channel)];
      for (int y = 0; y < out_rows; ++y) {
        const float* row_sums = channel_sums + static_cast<std::ptrdiff_t>(y) * padded_cols;
        float* out_row = out_plane + static_cast<std::ptrdiff_t>(y) * out_cols;
        for (int x = 0; x < out_cols; ++x) out_row[x] = row_sums[x] + bias;
      }
    }
  }

  // Stride 2 (either axis): per output row and tap, a strided row of the input.
  void AddStridedInput(const float* in_plane, int in_rows, int in_cols, const float* taps, int out_rows, int out_cols,
                       float* out_plane) const {
    const ConvGeometry& g = geometry_;
    for (int y = 0; y < out_rows; ++y) {
      float* out_row = out_plane + static_cast<std::ptrdiff_t>(y) * out_cols;
      for (int ky = 0; ky < g.kernel_h; ++ky) {
        const int in_y = y * g.stride_h - g.pad_top + ky * g.dilation_h;
        if (in_y < 0 || in_y >= in_rows) continue;  // a zero-padding row
        const float* in_row = in_plane + static_cast<std::ptrdiff_t>(in_y) * in_cols;
        for (int kx = 0; kx < g.kernel_w; ++kx)
          AddTapRow(kernels_, in_row, in_cols, taps[ky * g.kernel_w + kx], kx * g.dilation_w - g.pad_left,
                    g.stride_w, out_row, out_cols);
      }
    }
  }

  const ConvKernels& kernels_;  // the inner loops' build (semantic/conv_kernels.h)
  ConvGeometry geometry_;
  int groups_;               // > 1
  int outputs_ = 0;          // output channels, a multiple of groups_
  int inputs_per_group_ = 0; // 1..kMaxInputsPerGroup
  cv::Mat weights_;          // CV_32F [outputs_, inputs_per_group_, kernel_h, kernel_w], continuous
  std::vector<float> bias_;  // per output channel (zeros without a bias blob)
};

bool WeightsFit(const cv::dnn::LayerParams& params, int groups) {
  if (params.blobs.empty()) return false;
  const cv::Mat& w = params.blobs[0];
  if (w.dims != 4 || w.type() != CV_32F || !w.isContinuous()) return false;
  if (w.size[1] < 1 || w.size[1] > kMaxInputsPerGroup || w.size[0] % groups != 0) return false;
  if (params.blobs.size() > 2) return false;
  return params.blobs.size() == 1 ||
         (params.blobs[1].type() == CV_32F && params.blobs[1].total() == static_cast<std::size_t>(w.size[0]));
}

// The geometry of `params` where the layer computes them (GroupedConvolutionHandles), else
// nothing. Parses the params once.
std::optional<ConvGeometry> HandledGeometry(const cv::dnn::LayerParams& params) {
  const int groups = params.get<int>("group", 1);
  if (groups <= 1 || !WeightsFit(params, groups)) return std::nullopt;
  const std::optional<ConvGeometry> parsed = ParsedGeometry(params);
  if (!parsed) return std::nullopt;
  const ConvGeometry& g = *parsed;
  if (g.kernel_h < 1 || g.kernel_w < 1 || g.dilation_h < 1 || g.dilation_w < 1) return std::nullopt;
  if (g.stride_h < 1 || g.stride_h > 2 || g.stride_w < 1 || g.stride_w > 2) return std::nullopt;
  if (g.pad_top < 0 || g.pad_left < 0 || g.pad_bottom < 0 || g.pad_right < 0) return std::nullopt;
  if (params.blobs[0].size[2] != g.kernel_h || params.blobs[0].size[3] != g.kernel_w) return std::nullopt;
  return parsed;
}

}  // namespace

bool GroupedConvolutionHandles(const cv::dnn::LayerParams& params) { return HandledGeometry(params).has_value(); }

namespace {

// The grouped layer with `kernels` where it handles `params`, else OpenCV's.
cv::Ptr<cv::dnn::Layer> CreateWithKernels(cv::dnn::LayerParams& params, const ConvKernels& kernels) {
  if (const std::optional<ConvGeometry> geometry = HandledGeometry(params))
    return cv::makePtr<GroupedConvolutionLayer>(params, *geometry, kernels);
  return cv::dnn::ConvolutionLayer::create(params);
}

}  // namespace

cv::Ptr<cv::dnn::Layer> CreateConvolutionLayer(cv::dnn::LayerParams& params) {
  return CreateWithKernels(params, BestConvKernels());
}

cv::Ptr<cv::dnn::Layer> CreatePortableConvolutionLayer(cv::dnn::LayerParams& params) {
  return CreateWithKernels(params, PortableConvKernels());
}

bool IsGroupedConvolution(const cv::dnn::Layer& layer) {
  return dynamic_cast<const GroupedConvolutionLayer*>(&layer) != nullptr;
}

}  // namespace esdslam
