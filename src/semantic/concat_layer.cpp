#include "semantic/concat_layer.h"

#include <cstddef>
#include <cstring>
#include <vector>

#include <opencv2/dnn/all_layers.hpp>
#include <opencv2/dnn/layer.hpp>

#include "semantic/own_layer.h"

namespace esdslam {
namespace {

// The concatenation axis of a blob with `dims` axes (negative: counted from the last).
int ResolvedAxis(int axis, int dims) { return axis < 0 ? axis + dims : axis; }

// Product of shape[begin, end).
std::size_t Volume(const int* shape, int begin, int end) {
  std::size_t volume = 1;
  for (int d = begin; d < end; ++d) volume *= static_cast<std::size_t>(shape[d]);
  return volume;
}

class StridedConcatLayer final : public OwnLayer {
 public:
  explicit StridedConcatLayer(const cv::dnn::LayerParams& params) : axis_(params.get<int>("axis", 1)) {
    setParamsFrom(params);
  }

  // Inputs of one rank, equal on every axis but the concatenation axis -> their sum there.
  bool getMemoryShapes(const std::vector<cv::dnn::MatShape>& inputs, const int /*required_outputs*/,
                       std::vector<cv::dnn::MatShape>& outputs,
                       std::vector<cv::dnn::MatShape>& /*internals*/) const override {
    CV_Assert(!inputs.empty());
    const int dims = static_cast<int>(inputs[0].size());
    const int axis = ResolvedAxis(axis_, dims);
    CV_Check(axis, axis >= 1 && axis < dims, "concatenation axis out of range");
    cv::dnn::MatShape shape = inputs[0];
    for (std::size_t i = 1; i < inputs.size(); ++i) {
      CV_CheckEQ(static_cast<int>(inputs[i].size()), dims, "Concat inputs of different rank");
      for (int d = 0; d < dims; ++d)
        if (d != axis) CV_CheckEQ(inputs[i][static_cast<std::size_t>(d)], shape[static_cast<std::size_t>(d)],
                                  "Concat inputs differ off the concatenation axis");
      shape[static_cast<std::size_t>(axis)] += inputs[i][static_cast<std::size_t>(axis)];
    }
    outputs.assign(1, shape);
    return false;
  }

  void ForwardMats(const std::vector<cv::Mat>& inputs, std::vector<cv::Mat>& outputs) override {
    cv::Mat& out = outputs[0];
    CV_Assert(out.isContinuous());
    const int axis = ResolvedAxis(axis_, out.dims);
    const std::size_t element = out.elemSize();
    const std::size_t outer = Volume(out.size.p, 0, axis);
    // Bytes per outer index: of the output, and of each input's run.
    const std::size_t out_run = Volume(out.size.p, axis, out.dims) * element;
    std::vector<std::size_t> runs;
    for (const cv::Mat& in : inputs) {
      CV_Assert(in.isContinuous() && in.type() == out.type());
      runs.push_back(Volume(in.size.p, axis, in.dims) * element);
    }
    for (std::size_t o = 0; o < outer; ++o) {
      unsigned char* dst = out.data + o * out_run;
      for (std::size_t i = 0; i < inputs.size(); ++i) {
        const unsigned char* src = inputs[i].data + o * runs[i];
        if (runs[i] == sizeof(float)) {
          std::memcpy(dst, src, sizeof(float));  // a constant size: a single move, no call
        } else {
          std::memcpy(dst, src, runs[i]);
        }
        dst += runs[i];
      }
    }
  }

 private:
  int axis_;  // as given (negative: from the last axis); resolved per blob rank
};

}  // namespace

bool StridedConcatHandles(const cv::dnn::LayerParams& params) {
  if (params.get<bool>("padding", false)) return false;
  const int axis = params.get<int>("axis", 1);
  return axis >= 2 || axis == -1 || axis == -2;
}

cv::Ptr<cv::dnn::Layer> CreateConcatLayer(cv::dnn::LayerParams& params) {
  if (StridedConcatHandles(params)) return cv::makePtr<StridedConcatLayer>(params);
  return cv::dnn::ConcatLayer::create(params);
}

bool IsStridedConcat(const cv::dnn::Layer& layer) { return dynamic_cast<const StridedConcatLayer*>(&layer) != nullptr; }

}  // namespace esdslam
