#pragma once
// A separable bilinear Resize layer for OpenCV DNN. OpenCV 4.6's own Resize layer computes a
// bilinear output one pixel at a time, walking all channel planes per pixel (about 8 ms per
// ESPNetv2 call at 256x192 in the decoder's 19 mid-graph Resize layers; this layer about 1.1 ms,
// docs/RESULTS.md "Separable Resize layer"). This one precomputes, per output row and column,
// the two input indices and the weight of the second, then resizes each plane separably: the
// input rows to the output width, then each output row from two of those.
//
// It computes the modes OpenCV's layer computes in its own per-pixel loop, with the same
// coordinates: interpolation "bilinear" without half-pixel centres, one input blob and the output
// size given as width and height (what OpenCV's ONNX importer gives for a Resize with constant
// sizes), and
//   align_corners = true  ("align_corners"): output pixel i samples the input at
//                          i (in - 1) / (out - 1) (i in / out when out is 1, i.e. 0);
//   align_corners = false ("asymmetric"):    output pixel i samples the input at i in / out.
// The scale and the sampling position are float, truncated to the first index, as OpenCV does,
// so the indices and weights are OpenCV's; the blend differs only in float rounding (OpenCV
// blends the four neighbours in one expression, this blends along x, then along y).
// Other params (nearest, half-pixel centres, "opencv_linear", zoom factors) get OpenCV's own
// ResizeLayer.

#include <opencv2/dnn.hpp>

namespace esdslam {

// True when `params` (of a "Resize" layer) are a mode the separable layer computes (see above).
bool SeparableResizeHandles(const cv::dnn::LayerParams& params);

// The Resize layer for `params`: the separable one where SeparableResizeHandles, else OpenCV's
// cv::dnn::ResizeLayer::create(params). A cv::dnn::LayerFactory constructor: registered for
// "Resize" with ScopedLayerConstructor (semantic/own_layer.h).
cv::Ptr<cv::dnn::Layer> CreateResizeLayer(cv::dnn::LayerParams& params);

// True when `layer` is the separable layer (not OpenCV's).
bool IsSeparableResize(const cv::dnn::Layer& layer);

}  // namespace esdslam
