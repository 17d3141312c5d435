// The whole system (tracking + local mapping) on a short synthetic static sequence.
#include <gtest/gtest.h>

#include "eval/ate.h"
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
