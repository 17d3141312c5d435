// The whole system (tracking + local mapping) on a short synthetic static sequence.
#include <gtest/gtest.h>

#include "eval/ate.h"
#include "map/keyframe.h"
#include "map/map_point.h"
#include "synth/synthetic_scene.h"
#include "system/slam_system.h"

namespace esdslam {
namespace {

constexpr int kFrames = 45;

const SyntheticScene& Scene() {
  static const SyntheticScene scene([] {
    SynthOptions options = SynthPreset("static");
    options.num_frames = kFrames;
    options.supersampling = 1;
    return options;
  }());
  return scene;
}

const std::vector<SynthFrame>& Frames() {
  static const std::vector<SynthFrame> frames = [] {
    std::vector<SynthFrame> out;
    for (int i = 0; i < kFrames; ++i) out.push_back(Scene().RenderFrame(i));
    return out;
  }();
  return frames;
}

Settings SceneSettings() {
  Settings settings;
  settings.camera = Scene().camera().intrinsics();
  return settings;
}

std::vector<StampedPose> RunSystem(bool single_thread, int* tracked) {
  SlamOptions options;
  options.single_thread = single_thread;
  SlamSystem system(SceneSettings(), options);
  *tracked = 0;
  for (const SynthFrame& frame : Frames()) *tracked += system.TrackRgbd(frame.bgr, frame.depth_m, frame.timestamp).has_pose;
  system.Shutdown();
  EXPECT_GE(system.num_keyframes(), 2);
  EXPECT_EQ(system.KeyFrameTrajectory().size(), static_cast<std::size_t>(system.num_keyframes()));
  return system.Trajectory();
}

TEST(SlamSystemTest, SingleThreadTracksEveryFrameAccuratelyAndRepeats) {
  int tracked = 0;
  const auto first = RunSystem(true, &tracked);
  EXPECT_EQ(tracked, kFrames);
  ASSERT_EQ(first.size(), static_cast<std::size_t>(kFrames));
  const AteResult ate = ComputeAte(Scene().GroundTruth(), first);
  EXPECT_LT(ate.translation_m.rmse, 0.005);
  // The first keyframe defines the world: the first pose is the identity.
  EXPECT_LT(first.front().world_from_cam.translation().norm(), 1e-9);

  const auto second = RunSystem(true, &tracked);
  ASSERT_EQ(second.size(), first.size());
  for (std::size_t i = 0; i < first.size(); ++i) {
    EXPECT_EQ(first[i].world_from_cam.translation(), second[i].world_from_cam.translation()) << i;
    EXPECT_EQ(first[i].world_from_cam.rotation().coeffs(), second[i].world_from_cam.rotation().coeffs()) << i;
  }
}

TEST(SlamSystemTest, ThreadedModeTracksEveryFrameAndShutsDownCleanly) {
  int tracked = 0;
  const auto trajectory = RunSystem(false, &tracked);
  EXPECT_EQ(tracked, kFrames);
  const AteResult ate = ComputeAte(Scene().GroundTruth(), trajectory);
  EXPECT_LT(ate.translation_m.rmse, 0.006);
}

// A keyframe's dynamic mask that came after it was made (the first labels of a threaded run):
// the live points it observes at keypoints on the mask are removed, the others stay.
TEST(SlamSystemTest, RemovePointsUnderALateMaskRemovesOnlyThePointsOnIt) {
  SlamOptions options;
  options.single_thread = true;
  SlamSystem system(SceneSettings(), options);
  const SynthFrame& frame = Frames().front();
  const TrackOutcome outcome = system.TrackRgbd(frame.bgr, frame.depth_m, frame.timestamp);
  ASSERT_TRUE(outcome.new_keyframe);
  KeyFrame* keyframe = outcome.keyframe;
  cv::Mat left_half = cv::Mat::zeros(frame.bgr.size(), CV_8U);
  left_half.colRange(0, frame.bgr.cols / 2).setTo(255);
  const auto count_points = [&](bool left) {
    int n = 0;
    for (int i = 0; i < keyframe->features().size(); ++i) {
      const MapPoint* point = keyframe->map_point(i);
      if (point == nullptr || point->is_bad()) continue;
      n += (cvRound(keyframe->features().keypoints[i].pt.x) < frame.bgr.cols / 2) == left;
    }
    return n;
  };
  const int left_before = count_points(true), right_before = count_points(false);
  ASSERT_GT(left_before, 50);
  ASSERT_GT(right_before, 50);
  EXPECT_EQ(system.RemovePointsUnder(keyframe, left_half), left_before);
  EXPECT_EQ(count_points(true), 0);
  EXPECT_EQ(count_points(false), right_before);
  EXPECT_EQ(system.num_map_points(), right_before);
  const auto late = keyframe->late_dynamic();
  ASSERT_NE(late, nullptr);
  for (int i = 0; i < keyframe->features().size(); ++i)
    EXPECT_EQ((*late)[i] != 0, cvRound(keyframe->features().keypoints[i].pt.x) < frame.bgr.cols / 2) << i;
  EXPECT_EQ(system.RemovePointsUnder(keyframe, left_half), 0);
  EXPECT_EQ(system.RemovePointsUnder(keyframe, cv::Mat()), 0);
  // Tracking goes on in the remaining map.
  EXPECT_TRUE(system.TrackRgbd(Frames()[1].bgr, Frames()[1].depth_m, Frames()[1].timestamp).has_pose);
}

TEST(SlamSystemTest, RejectsMismatchedImagesAndUseAfterShutdown) {
  SlamSystem system(SceneSettings(), SlamOptions{});
  const SynthFrame& frame = Frames().front();
  EXPECT_THROW(system.TrackRgbd(frame.bgr, cv::Mat(), frame.timestamp), Error);
  EXPECT_THROW(system.TrackRgbd(frame.bgr, cv::Mat::zeros(10, 10, CV_32F), frame.timestamp), Error);
  system.Shutdown();
  EXPECT_THROW(system.TrackRgbd(frame.bgr, frame.depth_m, frame.timestamp), Error);
}

}  // namespace
}  // namespace esdslam
