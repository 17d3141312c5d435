// Frame construction and tracking (without local mapping) on the synthetic static scene.
#include <gtest/gtest.h>

#include "eval/ate.h"
#include "map/keyframe.h"
#include "map/map_point.h"
#include "synth/synthetic_scene.h"
#include "tracking/frame.h"
#include "tracking/tracker.h"

namespace esdslam {
namespace {

SynthOptions ShortStaticScene(int frames) {
  SynthOptions options = SynthPreset("static");
  options.num_frames = frames;
  options.supersampling = 1;  // fast rendering
  return options;
}

TEST(FrameTest, DepthAndVirtualRightCoordinate) {
  const SyntheticScene scene(ShortStaticScene(1));
  const SynthFrame image = scene.RenderFrame(0);
  const OrbExtractor extractor(OrbOptions{});
  const auto rig = MakeRgbdRig(scene.camera().intrinsics(), 40.0, 40.0, extractor);
  EXPECT_NEAR(rig->th_depth_m, 40.0 * 40.0 / scene.camera().fx(), 1e-12);
  cv::Mat mask(image.bgr.size(), CV_8U, cv::Scalar(0));
  mask(cv::Rect(0, 0, 320, 480)).setTo(255);  // left half "dynamic"
  const Frame frame(0, image.timestamp, image.bgr, image.depth_m, mask, extractor, rig);
  ASSERT_GT(frame.size(), 500);
  const FeatureSet& f = frame.features();
  int checked = 0;
  for (int i = 0; i < frame.size(); ++i) {
    const cv::KeyPoint& kp = f.keypoints[i];
    const float expected = image.depth_m.at<float>(cvRound(kp.pt.y), cvRound(kp.pt.x));
    EXPECT_FLOAT_EQ(f.depth[i], expected > 0 ? expected : 0.f);
    if (f.depth[i] > 0) {
      EXPECT_NEAR(f.right_u[i], f.undistorted[i].x - 40.0 / f.depth[i], 1e-3);
      ++checked;
    }
    EXPECT_EQ(f.is_dynamic[i] != 0, cvRound(kp.pt.x) < 320) << i;
  }
  EXPECT_GT(checked, 500);
}

TEST(TrackerTest, TracksShortStaticSequenceAccurately) {
  const int num_frames = 30;
  const SyntheticScene scene(ShortStaticScene(num_frames));
  const OrbExtractor extractor(OrbOptions{});
  const auto rig = MakeRgbdRig(scene.camera().intrinsics(), 40.0, 40.0, extractor);
  Map map;
  Tracker tracker(&map, nullptr, TrackerOptions{});
  std::vector<StampedPose> estimate;
  int keyframes_created = 0;
  for (int i = 0; i < num_frames; ++i) {
    const SynthFrame image = scene.RenderFrame(i);
    Frame frame(i, image.timestamp, image.bgr, image.depth_m, cv::Mat(), extractor, rig);
    const TrackingResult result = tracker.Track(&frame);
    ASSERT_TRUE(result.has_pose) << "frame " << i << " " << ToString(result.state);
    EXPECT_EQ(result.state, TrackingState::kOk);
    EXPECT_GE(result.inliers, 30);
    keyframes_created += result.new_keyframe != nullptr;
    estimate.push_back({image.timestamp, result.cam_from_world.inverse()});
  }
  EXPECT_GE(keyframes_created, 1);
  EXPECT_EQ(map.num_keyframes(), keyframes_created);
  const AteResult ate = ComputeAte(scene.GroundTruth(), estimate);
  EXPECT_LT(ate.translation_m.rmse, 0.01);  // visual odometry only: no local BA here
  EXPECT_EQ(ate.pairs.size(), static_cast<std::size_t>(num_frames));
}

TEST(TrackerTest, StaysUninitialisedWithoutDepth) {
  const SyntheticScene scene(ShortStaticScene(1));
  const SynthFrame image = scene.RenderFrame(0);
  const OrbExtractor extractor(OrbOptions{});
  const auto rig = MakeRgbdRig(scene.camera().intrinsics(), 40.0, 40.0, extractor);
  Map map;
  Tracker tracker(&map, nullptr, TrackerOptions{});
  Frame frame(0, image.timestamp, image.bgr, cv::Mat::zeros(image.depth_m.size(), CV_32F), cv::Mat(), extractor, rig);
  const TrackingResult result = tracker.Track(&frame);
  EXPECT_FALSE(result.has_pose);
  EXPECT_EQ(result.state, TrackingState::kNotInitialized);
  EXPECT_EQ(map.num_keyframes(), 0);
}

TEST(TrackerTest, ReportsLostOnUnrelatedImageAndRecovers) {
  const SyntheticScene scene(ShortStaticScene(12));
  const OrbExtractor extractor(OrbOptions{});
  const auto rig = MakeRgbdRig(scene.camera().intrinsics(), 40.0, 40.0, extractor);
  Map map;
  Tracker tracker(&map, nullptr, TrackerOptions{});
  for (int i = 0; i < 12; ++i) {
    SynthFrame image = scene.RenderFrame(i);
    if (i == 6) cv::randu(image.bgr, cv::Scalar::all(0), cv::Scalar::all(255));  // noise image
    Frame frame(i, image.timestamp, image.bgr, image.depth_m, cv::Mat(), extractor, rig);
    const TrackingResult result = tracker.Track(&frame);
    if (i == 6) {
      EXPECT_EQ(result.state, TrackingState::kLost);
      EXPECT_FALSE(result.has_pose);
    } else {
      EXPECT_TRUE(result.has_pose) << "frame " << i;
    }
  }
}

}  // namespace
}  // namespace esdslam
