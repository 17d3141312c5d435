// The mask predictor on synthetic scenes with known answers: a textured "person" box at 1.5 m
// moving with a known velocity in front of a textured wall at 3 m, the camera static or panning.
#include "dynamic/mask_predictor.h"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "common/error.h"

namespace esdslam {
namespace {

constexpr int kPerson = 15;
const cv::Size kSize(320, 240);
const cv::Rect kBoxAtStart(60, 50, 50, 150);

// Texture with structure at several scales (DIS needs gradients at every pyramid level).
cv::Mat Texture(cv::Size size, std::uint64_t seed) {
  cv::RNG rng(seed);
  cv::Mat sum = cv::Mat::zeros(size, CV_32F);
  for (int scale : {2, 6, 16}) {
    cv::Mat noise(size.height / scale + 2, size.width / scale + 2, CV_32F);
    rng.fill(noise, cv::RNG::UNIFORM, 0.0, 1.0);
    cv::Mat up;
    cv::resize(noise, up, cv::Size(noise.cols * scale, noise.rows * scale), 0, 0, cv::INTER_CUBIC);
    sum += up(cv::Rect(0, 0, size.width, size.height));
  }
  cv::Mat grey;
  sum.convertTo(grey, CV_8U, 255.0 / 3.0);
  return grey;
}

// Frame t of the scene: the wall seen through a window that pans by camera_px_per_frame, the box
// at kBoxAtStart shifted by box_px_per_frame (image motion, camera motion included).
struct Scene {
  int camera_px_per_frame = 0;
  int box_px_per_frame = 4;
  int shadow_px = 0;  // a band without depth beside the box's trailing edge (the projector's shadow)
  cv::Mat wall = Texture(cv::Size(kSize.width + 400, kSize.height), 1);
  cv::Mat box_texture = Texture(kBoxAtStart.size(), 2);

  cv::Rect Box(int t) const { return kBoxAtStart + cv::Point(box_px_per_frame * t, 0); }
  cv::Mat Grey(int t) const {
    cv::Mat grey = wall(cv::Rect(200 + camera_px_per_frame * t, 0, kSize.width, kSize.height)).clone();
    box_texture.copyTo(grey(Box(t)));
    return grey;
  }
  cv::Mat Depth(int t) const {
    cv::Mat depth(kSize, CV_32F, cv::Scalar(3.0f));
    depth(Box(t)).setTo(1.5f);
    if (shadow_px > 0) depth(cv::Rect(Box(t).x - shadow_px, Box(t).y, shadow_px, Box(t).height)).setTo(0.0f);
    return depth;
  }
  cv::Mat Labels(int t) const {
    cv::Mat labels = cv::Mat::zeros(kSize, CV_8U);
    labels(Box(t)).setTo(kPerson);
    return labels;
  }
};

MaskPredictorOptions SmallFlow() {
  MaskPredictorOptions options;
  options.flow_width_px = 160;
  options.flow_finest_scale = 1;
  return options;
}

double IoU(const cv::Mat& a, const cv::Mat& b) {
  const int uni = cv::countNonZero(a | b);
  return uni == 0 ? 1.0 : static_cast<double>(cv::countNonZero(a & b)) / uni;
}

cv::Mat BoxMask(const cv::Rect& box) {
  cv::Mat mask = cv::Mat::zeros(kSize, CV_8U);
  mask(box).setTo(255);
  return mask;
}

// Runs frames 0..last with labels of frame 0; returns the prediction for `last`.
MaskPrediction Carry(const Scene& scene, int last, const MaskPredictorOptions& options = SmallFlow()) {
  MaskPredictor predictor(kSize, options);
  for (int t = 0; t <= last; ++t) {
    predictor.AddFrame(t, scene.Grey(t), scene.Depth(t));
    if (t == 0) {
      EXPECT_TRUE(predictor.AddLabels(0, scene.Labels(0)));
    }
  }
  return predictor.Predict();
}

TEST(MaskPredictor, FollowsAnObjectMovingInFrontOfAStaticCamera) {
  const Scene scene;
  const int last = 10;  // 40 px: most of the box width
  const MaskPrediction p = Carry(scene, last);
  EXPECT_EQ(p.label_age, last);
  EXPECT_EQ(p.source_id, 0);
  const double followed = IoU(p.masks.dynamic, BoxMask(scene.Box(last)));
  const double held = IoU(BoxMask(scene.Box(0)), BoxMask(scene.Box(last)));
  std::printf("static camera, age %d: IoU %.3f (source mask where it was: %.3f)\n", last, followed, held);
  EXPECT_GT(followed, 0.85);
  EXPECT_LT(held, 0.3);
}

// The leading edge of the box covers the wall: the flow there is smeared towards the wall's, and
// those pixels, now nearer than what the previous frame saw, take the label of the box they join.
TEST(MaskPredictor, TheLeadingEdgeKeepsTheLabel) {
  const Scene scene;
  const int last = 10;
  const cv::Rect box = scene.Box(last);
  const cv::Mat leading = BoxMask(cv::Rect(box.x + box.width * 3 / 4, box.y, box.width / 4, box.height));
  auto recall = [&](const MaskPredictorOptions& options) {
    return cv::countNonZero(Carry(scene, last, options).masks.dynamic & leading) /
           static_cast<double>(cv::countNonZero(leading));
  };
  MaskPredictorOptions no_fill = SmallFlow();
  no_fill.disocclusion.fill_abs_tolerance_m = 0;
  const double filled = recall(SmallFlow()), unfilled = recall(no_fill);
  std::printf("leading quarter of the box labelled: %.3f (without the fill: %.3f)\n", filled, unfilled);
  EXPECT_GT(filled, 0.7);
  EXPECT_GT(filled, unfilled + 0.3);
}

TEST(MaskPredictor, FollowsTheObjectWhileTheCameraPans) {
  Scene scene;
  scene.camera_px_per_frame = 3;  // the wall moves left by 3 px per frame, the box right by 4
  const int last = 10;
  const MaskPrediction p = Carry(scene, last);
  const double followed = IoU(p.masks.dynamic, BoxMask(scene.Box(last)));
  std::printf("panning camera, age %d: IoU %.3f\n", last, followed);
  EXPECT_GT(followed, 0.85);
  // The wall's texture is carried too: the labels elsewhere stay background.
  EXPECT_EQ(cv::countNonZero(p.labels(cv::Rect(250, 0, 70, 240)) == kPerson), 0);
}

TEST(MaskPredictor, UncoveredBackgroundDoesNotInheritTheLabel) {
  const Scene scene;
  const int last = 10;
  const MaskPrediction p = Carry(scene, last);
  // Where the box was at frame 0 and is no longer: the wall, seen again.
  const cv::Mat uncovered = BoxMask(scene.Box(0)) & ~BoxMask(scene.Box(last));
  const double leaked = cv::countNonZero(p.masks.dynamic & uncovered) / static_cast<double>(cv::countNonZero(uncovered));
  MaskPredictorOptions no_test = SmallFlow();
  no_test.disocclusion.occlusion_abs_tolerance_m = 0;
  const MaskPrediction untested = Carry(scene, last, no_test);
  const double leaked_untested =
      cv::countNonZero(untested.masks.dynamic & uncovered) / static_cast<double>(cv::countNonZero(uncovered));
  std::printf("uncovered wall labelled: %.3f (without the disocclusion test: %.3f)\n", leaked, leaked_untested);
  EXPECT_LT(leaked, 0.1);
  EXPECT_GT(leaked_untested, leaked);
  EXPECT_GT(p.uncovered_fraction, 0.0);
}

// The background a person uncovers is first seen without depth (the sensor's shadow band moves
// with the person): the remembered depth still exposes it.
TEST(MaskPredictor, UncoveredBackgroundSeenFirstWithoutDepthDoesNotInheritTheLabel) {
  Scene scene;
  scene.shadow_px = 8;
  const int last = 10;
  const cv::Mat uncovered = BoxMask(scene.Box(0)) & ~BoxMask(scene.Box(last) + cv::Point(-scene.shadow_px, 0) +
                                                             cv::Size(scene.shadow_px, 0));
  auto leaked = [&](const MaskPredictorOptions& options) {
    const MaskPrediction p = Carry(scene, last, options);
    return cv::countNonZero(p.masks.dynamic & uncovered) / static_cast<double>(cv::countNonZero(uncovered));
  };
  MaskPredictorOptions forgetful = SmallFlow();
  forgetful.disocclusion.depth_memory_frames = 0;
  const double with_memory = leaked(SmallFlow()), without = leaked(forgetful);
  std::printf("uncovered wall labelled behind a shadow band: %.3f (no depth memory: %.3f)\n", with_memory, without);
  EXPECT_LT(with_memory, 0.1);
  EXPECT_GT(without, 0.5);
}

TEST(MaskPredictor, LateLabelsAreCarriedToTheCurrentFrameAsIfTheyHadComeOnTime) {
  const Scene scene;
  MaskPredictor on_time(kSize, SmallFlow()), late(kSize, SmallFlow());
  for (int t = 0; t <= 9; ++t) {
    on_time.AddFrame(t, scene.Grey(t), scene.Depth(t));
    late.AddFrame(t, scene.Grey(t), scene.Depth(t));
    if (t == 2) on_time.AddLabels(2, scene.Labels(2));
  }
  EXPECT_EQ(late.Predict().source_id, -1);
  EXPECT_TRUE(late.Predict().needs_labels);
  ASSERT_TRUE(late.AddLabels(2, scene.Labels(2)));  // arrives 7 frames late
  const MaskPrediction a = on_time.Predict(), b = late.Predict();
  EXPECT_EQ(b.label_age, 7);
  EXPECT_EQ(cv::countNonZero(a.labels != b.labels), 0);
  EXPECT_EQ(cv::countNonZero(a.masks.dynamic != b.masks.dynamic), 0);
  EXPECT_GT(IoU(b.masks.dynamic, BoxMask(scene.Box(9))), 0.85);
}

TEST(MaskPredictor, StaleFutureAndForgottenLabels) {
  const Scene scene;
  MaskPredictorOptions options = SmallFlow();
  options.history_frames = 4;
  MaskPredictor predictor(kSize, options);
  for (int t = 0; t <= 6; ++t) predictor.AddFrame(t, scene.Grey(t), scene.Depth(t));
  EXPECT_THROW(predictor.AddLabels(7, scene.Labels(6)), Error);   // frame not added yet
  EXPECT_FALSE(predictor.AddLabels(1, scene.Labels(1)));          // left the history (frames 3..6 kept)
  EXPECT_TRUE(predictor.AddLabels(4, scene.Labels(4)));
  EXPECT_FALSE(predictor.AddLabels(3, scene.Labels(3)));          // older than the labels in use
  EXPECT_EQ(predictor.source_frame(), 4);
  EXPECT_TRUE(predictor.AddLabels(6, scene.Labels(6)));
  EXPECT_EQ(predictor.Predict().label_age, 0);
  EXPECT_EQ(cv::countNonZero(predictor.Predict().masks.dynamic != BoxMask(scene.Box(6))), 0);
  EXPECT_THROW(predictor.AddFrame(6, scene.Grey(7), scene.Depth(7)), Error);        // id does not increase
  EXPECT_THROW(predictor.AddFrame(8, cv::Mat(10, 10, CV_8U), cv::Mat()), Error);    // wrong size
  EXPECT_THROW(predictor.AddLabels(6, cv::Mat(kSize, CV_16U)), Error);              // wrong type
}

TEST(MaskPredictor, TrustFallsWithAgeAndAsksForLabels) {
  const Scene scene;
  MaskPredictorOptions options = SmallFlow();
  options.max_trusted_age = 8;
  options.min_trust = 0.5;
  MaskPredictor predictor(kSize, options);
  double previous = 2.0;
  for (int t = 0; t <= 8; ++t) {
    predictor.AddFrame(t, scene.Grey(t), scene.Depth(t));
    if (t == 0) predictor.AddLabels(0, scene.Labels(0));
    const MaskPrediction p = predictor.Predict();
    EXPECT_LE(p.trust, previous);
    EXPECT_EQ(p.needs_labels, p.trust < 0.5) << t;
    previous = p.trust;
  }
  EXPECT_DOUBLE_EQ(previous, 0.0);
  EXPECT_TRUE(predictor.Predict().needs_labels);
}

TEST(MaskPredictor, SameInputsGiveIdenticalMasksWhateverOpenCVsThreadCount) {
  Scene scene;
  scene.camera_px_per_frame = 2;
  const int threads = cv::getNumThreads();
  cv::setNumThreads(1);
  const MaskPrediction one = Carry(scene, 8);
  cv::setNumThreads(std::max(2, threads));
  const MaskPrediction many = Carry(scene, 8);
  const MaskPrediction again = Carry(scene, 8);
  cv::setNumThreads(threads);
  EXPECT_EQ(cv::countNonZero(one.labels != many.labels), 0);
  EXPECT_EQ(cv::countNonZero(many.labels != again.labels), 0);
  EXPECT_EQ(cv::countNonZero(one.masks.dynamic != many.masks.dynamic), 0);
  EXPECT_DOUBLE_EQ(one.uncovered_fraction, many.uncovered_fraction);
}

TEST(MaskPredictor, AgeDilationGrowsTheMask) {
  const Scene scene;
  MaskPredictorOptions options = SmallFlow();
  const int plain = cv::countNonZero(Carry(scene, 6, options).masks.dynamic);
  options.age_dilation_px_per_frame = 1.0;
  options.max_age_dilation_px = 4;
  const int dilated = cv::countNonZero(Carry(scene, 6, options).masks.dynamic);
  // 4 px all round a 50 x 150 box: about 2 * 4 * (50 + 150) pixels more.
  EXPECT_GT(dilated - plain, 1200);
  EXPECT_LT(dilated - plain, 2000);
}

TEST(MaskPredictorOptions, ChecksBounds) {
  EXPECT_NO_THROW(MaskPredictorOptions{}.Check());
  MaskPredictorOptions o;
  o.flow_width_px = 8;
  EXPECT_THROW(o.Check(), Error);
  o = {};
  o.flow_patch_stride = 20;
  EXPECT_THROW(o.Check(), Error);
  o = {};
  o.min_trust = 1.5;
  EXPECT_THROW(o.Check(), Error);
  o = {};
  o.disocclusion.depth_memory_frames = -1;
  EXPECT_THROW(o.Check(), Error);
  EXPECT_THROW(MaskPredictor(cv::Size(16, 16)), Error);
}

}  // namespace
}  // namespace esdslam
