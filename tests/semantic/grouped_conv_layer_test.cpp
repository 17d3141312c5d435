// The grouped convolution and strided Concat layers against OpenCV DNN's own: each layer alone
// on noise blobs for the cases it computes (depthwise with dilation, stride and asymmetric pads;
// a few inputs and outputs per group; bias), which params it leaves to OpenCV, the scope of the
// registrations, and the shipped ESPNetv2 model loaded with and without them.
#include "semantic/grouped_conv_layer.h"

#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/dnn.hpp>
#include <opencv2/dnn/shape_utils.hpp>

#include "semantic/concat_layer.h"
#include "semantic/onnx_segmenter.h"
#include "semantic/own_layer.h"
#include "support/shipped_segmenter.h"

namespace esdslam {
namespace {

// A deterministic blob of `shape` with values in [-1, 1).
cv::Mat NoiseBlob(const std::vector<int>& shape, int seed) {
  cv::Mat blob(static_cast<int>(shape.size()), shape.data(), CV_32F);
  cv::RNG(static_cast<std::uint64_t>(seed)).fill(blob, cv::RNG::UNIFORM, -1.0, 1.0);
  return blob;
}

struct ConvCase {
  int inputs = 8, outputs = 8, groups = 8, kernel = 3, stride = 1, dilation = 1;
  int pad_top = 1, pad_left = 1, pad_bottom = 1, pad_right = 1;
  bool bias = false;
};

// Params as OpenCV's ONNX importer gives them for a Conv node, with noise weights.
cv::dnn::LayerParams ConvParams(const ConvCase& c, int seed) {
  cv::dnn::LayerParams params;
  params.name = "conv";
  params.type = "Convolution";
  params.set("kernel_size", cv::dnn::DictValue::arrayInt(std::vector<int>{c.kernel, c.kernel}.data(), 2));
  params.set("stride", cv::dnn::DictValue::arrayInt(std::vector<int>{c.stride, c.stride}.data(), 2));
  params.set("dilation", cv::dnn::DictValue::arrayInt(std::vector<int>{c.dilation, c.dilation}.data(), 2));
  const std::vector<int> pads{c.pad_top, c.pad_left, c.pad_bottom, c.pad_right};
  params.set("pad", cv::dnn::DictValue::arrayInt(pads.data(), 4));
  params.set("group", c.groups);
  params.set("num_output", c.outputs);
  params.set("bias_term", c.bias);
  params.blobs.push_back(NoiseBlob({c.outputs, c.inputs / c.groups, c.kernel, c.kernel}, seed));
  if (c.bias) params.blobs.push_back(NoiseBlob({c.outputs}, seed + 1000));
  return params;
}

// A one-layer net: `blob` through a layer with `params`, made while this project's layers are
// registered (a non-null `convolution` constructor: CreateConvolutionLayer or its portable
// twin, with CreateConcatLayer) or not. `is_ours`: whether the net holds this project's layer.
cv::Mat RunLayer(const cv::dnn::LayerParams& params, const std::vector<cv::Mat>& blobs,
                 cv::dnn::LayerFactory::Constructor convolution, bool* is_ours) {
  cv::dnn::Net net;
  {
    std::optional<ScopedLayerConstructor> grouped, strided;
    if (convolution != nullptr) {
      grouped.emplace("Convolution", convolution);
      strided.emplace("Concat", CreateConcatLayer);
    }
    cv::dnn::LayerParams copy = params;
    const int id = net.addLayer(params.name, params.type, copy);
    std::vector<cv::String> names;
    for (std::size_t i = 0; i < blobs.size(); ++i) {
      names.push_back("input" + std::to_string(i));
      net.connect(0, static_cast<int>(i), id, static_cast<int>(i));
    }
    net.setInputsNames(names);
    const cv::dnn::Layer& layer = *net.getLayer(id);  // getLayer creates the instance
    *is_ours = IsGroupedConvolution(layer) || IsStridedConcat(layer);
  }
  net.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
  net.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);
  for (std::size_t i = 0; i < blobs.size(); ++i) net.setInput(blobs[i], "input" + std::to_string(i));
  return net.forward().clone();
}

// Ours (with the inner loops the CPU runs best, and with the portable ones) and OpenCV's on the
// same blobs: the same shape, values within `tolerance`.
void ExpectSameAsOpenCv(const cv::dnn::LayerParams& params, const std::vector<cv::Mat>& blobs, double tolerance,
                        const std::string& what) {
  bool theirs = true;
  const cv::Mat reference = RunLayer(params, blobs, nullptr, &theirs);
  ASSERT_FALSE(theirs) << what;
  for (cv::dnn::LayerFactory::Constructor convolution : {CreateConvolutionLayer, CreatePortableConvolutionLayer}) {
    const std::string which = what + (convolution == CreateConvolutionLayer ? " (best loops)" : " (portable loops)");
    bool ours = false;
    const cv::Mat mine = RunLayer(params, blobs, convolution, &ours);
    ASSERT_TRUE(ours) << which;
    ASSERT_EQ(cv::dnn::shape(mine), cv::dnn::shape(reference)) << which;
    EXPECT_LE(cv::norm(mine, reference, cv::NORM_INF), tolerance) << which;
  }
}

// Sums of up to 8 x 9 products of values in [-1, 1): float rounding stays below 1e-5.
constexpr double kConvTolerance = 1e-5;

TEST(GroupedConvolution, DepthwiseMatchesOpenCv) {
  for (int dilation = 1; dilation <= 4; ++dilation) {  // the EESP blocks' dilations, pads = dilation
    ConvCase c;
    c.dilation = dilation;
    c.pad_top = c.pad_left = c.pad_bottom = c.pad_right = dilation;
    ExpectSameAsOpenCv(ConvParams(c, dilation), {NoiseBlob({1, 8, 12, 16}, 10 + dilation)}, kConvTolerance,
                       "dilation " + std::to_string(dilation));
    c.stride = 2;  // the downsampling blocks
    ExpectSameAsOpenCv(ConvParams(c, dilation), {NoiseBlob({1, 8, 13, 17}, 20 + dilation)}, kConvTolerance,
                       "stride 2, dilation " + std::to_string(dilation));
  }
  ConvCase wide_pad;  // pads wider than the kernel reach (the output grows), a 5x5 kernel, a batch of two, bias
  wide_pad.kernel = 5;
  wide_pad.pad_top = wide_pad.pad_left = wide_pad.pad_bottom = wide_pad.pad_right = 3;
  wide_pad.bias = true;
  ExpectSameAsOpenCv(ConvParams(wide_pad, 30), {NoiseBlob({2, 8, 9, 11}, 31)}, kConvTolerance, "wide pads");
  ConvCase unpadded;  // no pads: the output shrinks
  unpadded.pad_top = unpadded.pad_left = unpadded.pad_bottom = unpadded.pad_right = 0;
  ExpectSameAsOpenCv(ConvParams(unpadded, 32), {NoiseBlob({1, 8, 7, 5}, 33)}, kConvTolerance, "unpadded");
}

TEST(GroupedConvolution, SeveralInputsAndOutputsPerGroupMatchOpenCv) {
  ConvCase decoder;  // ESPNetv2's bu_dec merge: 50 inputs, 10 groups of 5 -> 1, bias
  decoder.inputs = 50;
  decoder.outputs = 10;
  decoder.groups = 10;
  decoder.bias = true;
  ExpectSameAsOpenCv(ConvParams(decoder, 40), {NoiseBlob({1, 50, 24, 32}, 41)}, kConvTolerance, "5 -> 1");
  ConvCase expansion;  // merge_enc_dec: 8 inputs -> 3 outputs per group
  expansion.inputs = 32;
  expansion.outputs = 12;
  expansion.groups = 4;
  expansion.bias = true;
  ExpectSameAsOpenCv(ConvParams(expansion, 42), {NoiseBlob({1, 32, 12, 16}, 43)}, kConvTolerance, "8 -> 3");
  expansion.stride = 2;
  ExpectSameAsOpenCv(ConvParams(expansion, 44), {NoiseBlob({1, 32, 12, 16}, 45)}, kConvTolerance, "8 -> 3, stride 2");
}

TEST(GroupedConvolution, GroupsSplitOverThreadsMatchOpenCv) {
  const int threads = cv::getNumThreads();
  cv::setNumThreads(2);  // process-wide: restored below
  ConvCase c;
  c.inputs = c.outputs = c.groups = 32;
  c.dilation = 2;
  c.pad_top = c.pad_left = c.pad_bottom = c.pad_right = 2;
  ExpectSameAsOpenCv(ConvParams(c, 50), {NoiseBlob({1, 32, 96, 128}, 51)}, kConvTolerance, "2 threads");
  cv::setNumThreads(threads);
}

TEST(GroupedConvolution, OtherParamsGetOpenCvsLayer) {
  ConvCase depthwise;
  EXPECT_TRUE(GroupedConvolutionHandles(ConvParams(depthwise, 1)));
  std::vector<cv::dnn::LayerParams> others;
  ConvCase full = depthwise;  // one group: OpenCV's GEMM
  full.groups = 1;
  others.push_back(ConvParams(full, 2));
  ConvCase wide = depthwise;  // 16 inputs per group: above kMaxInputsPerGroup
  wide.inputs = 32;
  wide.groups = 2;
  others.push_back(ConvParams(wide, 3));
  ConvCase stride3 = depthwise;
  stride3.stride = 3;
  others.push_back(ConvParams(stride3, 4));
  others.push_back(ConvParams(depthwise, 5));
  others.back().set("pad_mode", "SAME");
  ConvCase asymmetric = depthwise;  // OpenCV 4.6 rejects pads differing per side: so do we
  asymmetric.pad_top = 0;
  EXPECT_FALSE(GroupedConvolutionHandles(ConvParams(asymmetric, 6)));
  for (cv::dnn::LayerParams& params : others) {
    EXPECT_FALSE(GroupedConvolutionHandles(params));
    const cv::Ptr<cv::dnn::Layer> layer = CreateConvolutionLayer(params);
    ASSERT_FALSE(layer.empty());
    EXPECT_FALSE(IsGroupedConvolution(*layer));
  }
}

cv::dnn::LayerParams ConcatParams(int axis) {
  cv::dnn::LayerParams params;
  params.name = "concat";
  params.type = "Concat";
  params.set("axis", axis);
  return params;
}

TEST(StridedConcat, HeightAndWidthMatchOpenCvExactly) {
  // The decoder's interleave: runs of one float along the last axis.
  ExpectSameAsOpenCv(ConcatParams(3), {NoiseBlob({1, 180, 8, 1}, 60), NoiseBlob({1, 180, 8, 1}, 61)}, 0.0, "axis 3");
  ExpectSameAsOpenCv(ConcatParams(-1), {NoiseBlob({1, 4, 5, 2}, 62), NoiseBlob({1, 4, 5, 3}, 63)}, 0.0, "axis -1");
  ExpectSameAsOpenCv(ConcatParams(2), {NoiseBlob({1, 60, 1, 16}, 64), NoiseBlob({1, 60, 1, 16}, 65)}, 0.0, "axis 2");
  ExpectSameAsOpenCv(ConcatParams(-2),
                     {NoiseBlob({2, 3, 4, 5}, 66), NoiseBlob({2, 3, 1, 5}, 67), NoiseBlob({2, 3, 2, 5}, 68)}, 0.0,
                     "axis -2, three inputs, batch of two");
}

TEST(StridedConcat, ChannelsAndPaddingGetOpenCvsLayer) {
  EXPECT_TRUE(StridedConcatHandles(ConcatParams(3)));
  std::vector<cv::dnn::LayerParams> others{ConcatParams(1), ConcatParams(0), ConcatParams(-3), ConcatParams(2)};
  others.back().set("padding", true);
  for (cv::dnn::LayerParams& params : others) {
    EXPECT_FALSE(StridedConcatHandles(params));
    const cv::Ptr<cv::dnn::Layer> layer = CreateConcatLayer(params);
    ASSERT_FALSE(layer.empty());
    EXPECT_FALSE(IsStridedConcat(*layer));
  }
}

TEST(OwnLayers, RegistrationLastsForTheScopeOnly) {
  cv::dnn::LayerParams conv = ConvParams(ConvCase{}, 70);
  cv::dnn::LayerParams concat = ConcatParams(3);
  {
    ScopedLayerConstructor grouped("Convolution", CreateConvolutionLayer);
    ScopedLayerConstructor strided("Concat", CreateConcatLayer);
    EXPECT_TRUE(IsGroupedConvolution(*cv::dnn::LayerFactory::createLayerInstance("Convolution", conv)));
    EXPECT_TRUE(IsStridedConcat(*cv::dnn::LayerFactory::createLayerInstance("Concat", concat)));
  }
  const cv::Ptr<cv::dnn::Layer> conv_after = cv::dnn::LayerFactory::createLayerInstance("Convolution", conv);
  const cv::Ptr<cv::dnn::Layer> concat_after = cv::dnn::LayerFactory::createLayerInstance("Concat", concat);
  ASSERT_FALSE(conv_after.empty());  // OpenCV's constructors are back
  ASSERT_FALSE(concat_after.empty());
  EXPECT_FALSE(IsGroupedConvolution(*conv_after));
  EXPECT_FALSE(IsStridedConcat(*concat_after));
}

// --- The shipped model with and without the layers ---

using ::esdslam::testing::ExpectSameScores;
using ::esdslam::testing::ShippedSegmenter;

TEST(OwnLayers, ShippedModelGivesOpenCvsScores) {
  OnnxSegmenter ours = ShippedSegmenter(/*separable_resize=*/true, /*own_layers=*/true),
                reference = ShippedSegmenter(/*separable_resize=*/true, /*own_layers=*/false);
  EXPECT_EQ(ours.grouped_convolution_layers(), 87);  // 80 depthwise + 7 small grouped
  EXPECT_EQ(ours.strided_concat_layers(), 8);        // 2 interleaves in each of the 4 decoder stages
  EXPECT_EQ(reference.grouped_convolution_layers(), 0);
  EXPECT_EQ(reference.strided_concat_layers(), 0);
  cv::Mat noise(480, 640, CV_8UC3);
  cv::RNG(7).fill(noise, cv::RNG::UNIFORM, 0, 256);
  ExpectSameScores(ours, reference, noise, "noise image");
  ::esdslam::testing::ExpectSameScoresOnBonnFrames(ours, reference);
}

}  // namespace
}  // namespace esdslam
