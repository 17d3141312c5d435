#pragma once
// A convolution layer for OpenCV DNN for the grouped convolutions with few input channels per
// group: depthwise (one input channel per group) and the decoder's small grouped 3x3 convs
// (4-8 input channels per group). OpenCV 4.6 runs these at 2-4 GMAC/s, the dilated depthwise
// ones of ESPNetv2's EESP blocks on a scalar path: 80 depthwise and 6 small grouped layers took
// about 20 of the 39 ms of one ESPNetv2 call at 256x192 on one thread (docs/RESULTS.md,
// "Grouped convolution and strided concat layers").
//
// Per output channel, the output plane starts at zero; for each of the group's input channels
// and each kernel tap, a shifted row of the input plane times the tap's weight is added to each
// output row (a contiguous multiply-add along the row for stride 1; the inner loops are those of
// semantic/conv_kernels.h, AVX2+FMA where the CPU has it); the bias is added last. Taps that
// fall on the zero padding are skipped, which is the same as adding zero. The sums are OpenCV's up to float rounding (the order of the additions
// differs).
//
// Handled (GroupedConvolutionHandles): 2-D, explicit pads (no "SAME"/"VALID" pad mode), group
// count > 1, at most kMaxInputsPerGroup input channels per group, strides 1 or 2, float weights
// [out, in / group, kh, kw], optional bias. Everything else gets OpenCV's ConvolutionLayer.
// The layer does not fuse a following BatchNorm or activation (OpenCV then runs those as their
// own layers, which is the same computation).

#include <opencv2/dnn.hpp>

namespace esdslam {

// The largest number of input channels per group the layer takes. Above it OpenCV's GEMM path
// is the faster one (the EESP blocks' grouped 1x1 convs with 32-128 channels per group run at
// 20-30 GMAC/s there).
inline constexpr int kMaxInputsPerGroup = 8;

// True when `params` (of a "Convolution" layer) are a case the layer computes (see above).
bool GroupedConvolutionHandles(const cv::dnn::LayerParams& params);

// The Convolution layer for `params`: the grouped one where GroupedConvolutionHandles, else
// OpenCV's cv::dnn::ConvolutionLayer::create(params). A cv::dnn::LayerFactory constructor:
// registered for "Convolution" with ScopedLayerConstructor (semantic/own_layer.h).
cv::Ptr<cv::dnn::Layer> CreateConvolutionLayer(cv::dnn::LayerParams& params);
// The same with the portable inner loops whatever the CPU (for comparisons).
cv::Ptr<cv::dnn::Layer> CreatePortableConvolutionLayer(cv::dnn::LayerParams& params);

// True when `layer` is the grouped layer (not OpenCV's).
bool IsGroupedConvolution(const cv::dnn::Layer& layer);

}  // namespace esdslam
