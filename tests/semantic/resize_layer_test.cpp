// The separable Resize layer against OpenCV DNN's own: the layer alone on small blobs for each
// mode it computes, which params it leaves to OpenCV, the scope of its registration, and the
// shipped ESPNetv2 model loaded with and without it.
#include "semantic/resize_layer.h"

#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/dnn.hpp>
#include <opencv2/dnn/shape_utils.hpp>
#include <opencv2/imgproc.hpp>

#include "semantic/onnx_segmenter.h"
#include "semantic/own_layer.h"
#include "support/shipped_segmenter.h"

namespace esdslam {
namespace {

cv::dnn::LayerParams ResizeParams(int width, int height, bool align_corners, const std::string& mode) {
  cv::dnn::LayerParams params;
  params.name = "resize";
  params.type = "Resize";
  params.set("interpolation", "bilinear");
  params.set("align_corners", align_corners);
  params.set("coordinate_transformation_mode", mode);  // as OpenCV's ONNX importer leaves it
  params.set("width", width);
  params.set("height", height);
  return params;
}

// A deterministic blob of `shape` with values in [-1, 1).
cv::Mat NoiseBlob(const std::vector<int>& shape, int seed) {
  cv::Mat blob(static_cast<int>(shape.size()), shape.data(), CV_32F);
  cv::RNG(static_cast<std::uint64_t>(seed)).fill(blob, cv::RNG::UNIFORM, -1.0, 1.0);
  return blob;
}

// A one-layer net: `blob` through a Resize with `params`, made while the separable layer is
// registered (separable) or not. `is_separable`: which layer the net holds.
cv::Mat RunResize(const cv::dnn::LayerParams& params, const cv::Mat& blob, bool separable, bool* is_separable) {
  cv::dnn::Net net;
  {
    std::optional<ScopedLayerConstructor> scope;
    if (separable) scope.emplace("Resize", CreateResizeLayer);
    cv::dnn::LayerParams copy = params;
    const int id = net.addLayerToPrev(params.name, params.type, copy);
    *is_separable = IsSeparableResize(*net.getLayer(id));  // getLayer creates the instance
  }
  net.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
  net.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);
  net.setInput(blob);
  return net.forward().clone();
}

// The separable layer and OpenCV's on the same blob: the same shape, values within 2e-6
// (inputs in [-1, 1): float rounding of the blend only).
void ExpectSameAsOpenCv(const cv::dnn::LayerParams& params, const cv::Mat& blob) {
  bool ours = false, theirs = true;
  const cv::Mat separable = RunResize(params, blob, true, &ours);
  const cv::Mat reference = RunResize(params, blob, false, &theirs);
  ASSERT_TRUE(ours);
  ASSERT_FALSE(theirs);
  ASSERT_EQ(separable.dims, 4);
  ASSERT_EQ(cv::dnn::shape(separable), cv::dnn::shape(reference));
  EXPECT_EQ(separable.size[2], params.get<int>("height"));
  EXPECT_EQ(separable.size[3], params.get<int>("width"));
  EXPECT_LE(cv::norm(separable, reference, cv::NORM_INF), 2e-6)
      << params.get<std::string>("coordinate_transformation_mode") << " " << blob.size[2] << "x" << blob.size[3]
      << " -> " << separable.size[2] << "x" << separable.size[3];
}

TEST(SeparableResize, AlignCornersMatchesOpenCv) {
  // The decoder's sizes: 2x, 1.5x and odd ratios from tiny pooled maps, several channels.
  ExpectSameAsOpenCv(ResizeParams(32, 24, true, "align_corners"), NoiseBlob({1, 10, 12, 16}, 1));
  ExpectSameAsOpenCv(ResizeParams(24, 18, true, "align_corners"), NoiseBlob({1, 10, 12, 16}, 2));
  ExpectSameAsOpenCv(ResizeParams(16, 12, true, "align_corners"), NoiseBlob({1, 10, 5, 5}, 3));
  ExpectSameAsOpenCv(ResizeParams(64, 48, true, "align_corners"), NoiseBlob({1, 3, 5, 7}, 4));
  ExpectSameAsOpenCv(ResizeParams(256, 192, true, "align_corners"), NoiseBlob({1, 2, 96, 128}, 5));
  // Downsampling (rows no output reads are skipped), a batch of two, one output pixel.
  ExpectSameAsOpenCv(ResizeParams(13, 10, true, "align_corners"), NoiseBlob({2, 3, 24, 32}, 6));
  ExpectSameAsOpenCv(ResizeParams(1, 1, true, "align_corners"), NoiseBlob({1, 2, 4, 6}, 7));
}

TEST(SeparableResize, AsymmetricMatchesOpenCv) {
  ExpectSameAsOpenCv(ResizeParams(32, 24, false, "asymmetric"), NoiseBlob({1, 10, 12, 16}, 11));
  ExpectSameAsOpenCv(ResizeParams(16, 12, false, "asymmetric"), NoiseBlob({1, 4, 5, 7}, 12));
  ExpectSameAsOpenCv(ResizeParams(13, 10, false, "asymmetric"), NoiseBlob({2, 3, 24, 32}, 13));
  cv::dnn::LayerParams no_mode = ResizeParams(40, 30, false, "asymmetric");
  no_mode.erase("coordinate_transformation_mode");  // a net built by hand: align_corners alone
  ExpectSameAsOpenCv(no_mode, NoiseBlob({1, 3, 9, 11}, 14));
}

TEST(SeparableResize, PlanesSplitOverThreadsMatchOpenCv) {
  const int threads = cv::getNumThreads();
  cv::setNumThreads(2);  // process-wide: restored below
  ExpectSameAsOpenCv(ResizeParams(256, 192, true, "align_corners"), NoiseBlob({1, 10, 96, 128}, 15));
  ExpectSameAsOpenCv(ResizeParams(21, 17, false, "asymmetric"), NoiseBlob({2, 5, 8, 9}, 16));
  cv::setNumThreads(threads);
}

TEST(SeparableResize, SameSizeIsACopy) {
  const cv::Mat blob = NoiseBlob({1, 3, 6, 8}, 21);
  bool ours = false;
  const cv::Mat out = RunResize(ResizeParams(8, 6, true, "align_corners"), blob, true, &ours);
  ASSERT_TRUE(ours);
  EXPECT_EQ(cv::norm(out, blob, cv::NORM_INF), 0.0);
}

TEST(SeparableResize, OtherParamsGetOpenCvsLayer) {
  EXPECT_TRUE(SeparableResizeHandles(ResizeParams(32, 24, true, "align_corners")));
  EXPECT_TRUE(SeparableResizeHandles(ResizeParams(32, 24, false, "asymmetric")));
  std::vector<cv::dnn::LayerParams> others;
  others.push_back(ResizeParams(32, 24, false, "half_pixel"));  // the importer leaves align_corners 0
  others.push_back(ResizeParams(32, 24, false, "pytorch_half_pixel"));
  others.push_back(ResizeParams(32, 24, true, "asymmetric"));  // contradictory
  others.push_back(ResizeParams(32, 24, false, "asymmetric"));
  others.back().set("interpolation", "nearest");
  others.push_back(ResizeParams(32, 24, false, "asymmetric"));
  others.back().set("interpolation", "opencv_linear");
  others.push_back(ResizeParams(32, 24, false, "asymmetric"));
  others.back().set("half_pixel_centers", true);
  others.push_back(ResizeParams(32, 24, true, "align_corners"));
  others.back().set("zoom_factor_x", 2.0f);
  others.back().set("zoom_factor_y", 2.0f);
  others.push_back(ResizeParams(0, 0, true, "align_corners"));  // no size
  for (cv::dnn::LayerParams& params : others) {
    EXPECT_FALSE(SeparableResizeHandles(params));
    const cv::Ptr<cv::dnn::Layer> layer = CreateResizeLayer(params);
    ASSERT_FALSE(layer.empty());
    EXPECT_FALSE(IsSeparableResize(*layer));
  }
  // Through the factory on a net: the same result as OpenCV's layer, because it is OpenCV's.
  cv::dnn::LayerParams half_pixel = ResizeParams(32, 24, false, "asymmetric");
  half_pixel.set("interpolation", "opencv_linear");
  bool ours = true;
  RunResize(half_pixel, NoiseBlob({1, 2, 12, 16}, 31), true, &ours);
  EXPECT_FALSE(ours);
}

TEST(SeparableResize, RegistrationLastsForTheScopeOnly) {
  cv::dnn::LayerParams params = ResizeParams(32, 24, true, "align_corners");
  {
    ScopedLayerConstructor scope("Resize", CreateResizeLayer);
    EXPECT_TRUE(IsSeparableResize(*cv::dnn::LayerFactory::createLayerInstance("Resize", params)));
  }
  const cv::Ptr<cv::dnn::Layer> after = cv::dnn::LayerFactory::createLayerInstance("Resize", params);
  ASSERT_FALSE(after.empty());  // OpenCV's constructor is back, not unregistered
  EXPECT_FALSE(IsSeparableResize(*after));
  {
    ScopedLayerConstructor again("Resize", CreateResizeLayer);  // a second registration works as the first
    EXPECT_TRUE(IsSeparableResize(*cv::dnn::LayerFactory::createLayerInstance("Resize", params)));
  }
  EXPECT_FALSE(IsSeparableResize(*cv::dnn::LayerFactory::createLayerInstance("Resize", params)));
}

// --- The shipped model with and without the separable layer ---

using ::esdslam::testing::ExpectSameScores;
using ::esdslam::testing::ShippedSegmenter;

TEST(SeparableResize, ShippedModelGivesOpenCvsScores) {
  OnnxSegmenter separable = ShippedSegmenter(/*separable_resize=*/true, /*own_layers=*/true),
                reference = ShippedSegmenter(/*separable_resize=*/false, /*own_layers=*/true);
  EXPECT_EQ(separable.separable_resize_layers(), 20);  // every Resize of ESPNetv2's decoder
  EXPECT_EQ(reference.separable_resize_layers(), 0);
  cv::Mat noise(480, 640, CV_8UC3);
  cv::RNG(7).fill(noise, cv::RNG::UNIFORM, 0, 256);
  ExpectSameScores(separable, reference, noise, "noise image");
  cv::Mat blocks(480, 640, CV_8UC3);  // smooth regions with edges: several classes compete
  cv::RNG(8).fill(blocks, cv::RNG::UNIFORM, 0, 256);
  cv::Mat small;
  cv::resize(blocks, small, cv::Size(8, 6), 0, 0, cv::INTER_AREA);
  cv::resize(small, blocks, blocks.size(), 0, 0, cv::INTER_NEAREST);
  ExpectSameScores(separable, reference, blocks, "block image");
}

TEST(SeparableResize, ShippedModelGivesOpenCvsScoresOnBonnFrames) {
  OnnxSegmenter separable = ShippedSegmenter(/*separable_resize=*/true, /*own_layers=*/true),
                reference = ShippedSegmenter(/*separable_resize=*/false, /*own_layers=*/true);
  ::esdslam::testing::ExpectSameScoresOnBonnFrames(separable, reference);
}

}  // namespace
}  // namespace esdslam
