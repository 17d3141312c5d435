// The mask stage at a reduced resolution: the block helpers have known answers, and region
// growing on the halved image gives the full-resolution silhouette up to its 2x2-pixel steps.
#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "common/error.h"
#include "common/setting_error.h"
#include "dynamic/mask_dilation.h"
#include "dynamic/mask_refine.h"
#include "dynamic/region_growing.h"
#include "synth/synthetic_scene.h"

namespace esdslam {
namespace {

double IoU(const cv::Mat& a, const cv::Mat& b) {
  const int inter = cv::countNonZero((a != 0) & (b != 0));
  const int uni = cv::countNonZero((a != 0) | (b != 0));
  return uni == 0 ? 1.0 : static_cast<double>(inter) / uni;
}

TEST(MaskRefine, ReduceMaskAnyKeepsEveryMaskedPixelsBlock) {
  cv::Mat mask = cv::Mat::zeros(5, 7, CV_8U);  // odd sizes: the last blocks are cut
  mask.at<std::uint8_t>(0, 0) = 1;
  mask.at<std::uint8_t>(3, 5) = 9;
  mask.at<std::uint8_t>(4, 6) = 255;
  const cv::Mat small = ReduceMaskAny(mask, 2);
  ASSERT_EQ(small.size(), cv::Size(4, 3));
  cv::Mat expected = cv::Mat::zeros(3, 4, CV_8U);
  expected.at<std::uint8_t>(0, 0) = 255;
  expected.at<std::uint8_t>(1, 2) = 255;
  expected.at<std::uint8_t>(2, 3) = 255;
  EXPECT_EQ(cv::countNonZero(small != expected), 0);
  EXPECT_EQ(ReduceMaskAny(mask, 1).data, mask.data);  // factor 1: shared
}

TEST(MaskRefine, SubsampleDepthTakesEachBlocksFirstPixel) {
  cv::Mat depth(5, 5, CV_32F);
  for (int v = 0; v < 5; ++v)
    for (int u = 0; u < 5; ++u) depth.at<float>(v, u) = static_cast<float>(10 * v + u);
  const cv::Mat small = SubsampleDepth(depth, 2);
  ASSERT_EQ(small.size(), cv::Size(3, 3));
  EXPECT_EQ(small.at<float>(0, 0), 0.0f);
  EXPECT_EQ(small.at<float>(1, 2), 24.0f);
  EXPECT_EQ(small.at<float>(2, 2), 44.0f);
}

TEST(MaskRefine, EnlargeNearestInvertsTheBlockLayout) {
  cv::Mat small(3, 4, CV_8U);
  cv::randu(small, 0, 256);
  const cv::Size size(7, 5);
  const cv::Mat big = EnlargeNearest(small, 2, size);
  ASSERT_EQ(big.size(), size);
  for (int v = 0; v < size.height; ++v)
    for (int u = 0; u < size.width; ++u) ASSERT_EQ(big.at<std::uint8_t>(v, u), small.at<std::uint8_t>(v / 2, u / 2));
  // The same as cv::resize's nearest neighbour for an exact factor.
  cv::Mat by_opencv;
  cv::resize(small, by_opencv, cv::Size(16, 12), 0, 0, cv::INTER_NEAREST);
  EXPECT_EQ(cv::countNonZero(EnlargeNearest(small, 4, cv::Size(16, 12)) != by_opencv), 0);
  for (const int factor : {3, 4}) {  // partial blocks at the right and bottom edges
    const cv::Size partial(4 * factor - 1, 3 * factor - 2);
    const cv::Mat enlarged = EnlargeNearest(small, factor, partial);
    ASSERT_EQ(enlarged.size(), partial);
    for (int v = 0; v < partial.height; ++v)
      for (int u = 0; u < partial.width; ++u)
        ASSERT_EQ(enlarged.at<std::uint8_t>(v, u), small.at<std::uint8_t>(v / factor, u / factor)) << factor;
  }
  EXPECT_THROW(EnlargeNearest(small, 1, size), Error);  // 4x3 cannot cover 7x5
  EXPECT_THROW(ReduceMaskAny(small, 0), Error);
  EXPECT_THROW(SubsampleDepth(small, 2), Error);  // not depth
}

TEST(MaskRefine, OptionsCheckNamesTheKey) {
  MaskRefineOptions options;
  EXPECT_NO_THROW(options.Check());
  options.scale = 0;
  try {
    options.Check();
    FAIL() << "scale 0 accepted";
  } catch (const SettingError& e) {
    EXPECT_NE(std::string(e.what()).find("Dynamic.refineScale"), std::string::npos) << e.what();
  }
  options = {};
  options.dilation_px = -1;
  EXPECT_THROW(options.Check(), SettingError);
}

// Region growing on the halved depth, enlarged back, against full resolution and against the
// true silhouettes of the synthetic movers (coarse masks as a network gives them).
TEST(MaskRefine, HalvedGrowingMatchesFullResolution) {
  SynthOptions synth = SynthPreset("dynamic");
  synth.num_frames = 60;
  const SyntheticScene scene(synth);
  RegionGrowingOptions half_options;
  half_options.seed_erosion_px = 2;
  half_options.growth_band_px = 8;
  half_options.no_depth_dilation_px = 1;
  half_options.min_component_px = 30 / 4;
  int cases = 0;
  for (const int index : {0, 20, 40, 59}) {
    const SynthFrame frame = scene.RenderFrame(index);
    const cv::Mat truth = frame.mover_mask != 0;
    if (cv::countNonZero(truth) < 2000) continue;
    const cv::Mat coarse = DilateEllipse(truth, 8);  // bleeds onto the background
    const cv::Mat full = RefineDynamicMask(coarse, frame.depth_m, RegionGrowingOptions{});
    const cv::Mat half = EnlargeNearest(
        RefineDynamicMask(ReduceMaskAny(coarse, 2), SubsampleDepth(frame.depth_m, 2), half_options), 2, truth.size());
    EXPECT_GT(IoU(half, full), 0.95) << "frame " << index;
    EXPECT_GT(IoU(half, truth), IoU(coarse, truth)) << "frame " << index;
    EXPECT_GT(IoU(half, truth), 0.9) << "frame " << index;
    ++cases;
  }
  EXPECT_GE(cases, 2);
}

}  // namespace
}  // namespace esdslam
