#pragma once
// A Concat layer for OpenCV DNN for concatenation along an axis after the channels (height or
// width of an N x C x H x W blob). ESPNetv2's decoder interleaves pooled planes that way: its
// largest such Concat joins two 1440 x 64 x 1 blobs into 1440 x 64 x 2. OpenCV 4.6 copies each
// input into a strided view of the output, which with runs of one float took about 1.6 ms of
// one 256x192 call (docs/RESULTS.md, "Grouped convolution and strided concat layers"). This one
// copies, per index of the axes before the concatenation axis, each input's run in turn: the
// same output, bit for bit.
//
// Handled (StridedConcatHandles): a non-negative axis >= 2 or a negative one (counted from the
// last axis, -1 or -2), no padding. Concatenation along the channels (axis 1) keeps OpenCV's
// layer, which can have the inputs written straight into the output.

#include <opencv2/dnn.hpp>

namespace esdslam {

// True when `params` (of a "Concat" layer) are a case the layer computes (see above).
bool StridedConcatHandles(const cv::dnn::LayerParams& params);

// The Concat layer for `params`: the strided one where StridedConcatHandles, else OpenCV's
// cv::dnn::ConcatLayer::create(params). A cv::dnn::LayerFactory constructor: registered for
// "Concat" with ScopedLayerConstructor (semantic/own_layer.h).
cv::Ptr<cv::dnn::Layer> CreateConcatLayer(cv::dnn::LayerParams& params);

// True when `layer` is the strided layer (not OpenCV's).
bool IsStridedConcat(const cv::dnn::Layer& layer);

}  // namespace esdslam
