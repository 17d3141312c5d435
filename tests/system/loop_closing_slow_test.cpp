// Loop closing end to end (single thread, so every run repeats exactly):
//   - the synthetic loop (one turn around the room, back to the start pose, with depth noise so
//     that the open-loop drift is clearly measurable): the loop is detected and closing it at
//     least halves the ATE of the same run with loop closing off;
//   - sequences without revisits (synthetic static / dynamic presets, TUM fr1_rpy and Bonn crowd
//     dev windows): no loop is closed, and the trajectory is the one of loop closing off.
#include <gtest/gtest.h>

#include <filesystem>

#include "eval/ate.h"
#include "io/settings.h"
#include "io/tum_sequence.h"
#include "synth/synthetic_scene.h"
#include "system/slam_system.h"

namespace esdslam {
namespace {

const std::string kData = std::string(ESDSLAM_TEST_DATA_DIR) + "/data/";

struct LoopRun {
  int tracked = 0, frames = 0;
  double ate_rmse = 0;
  LoopClosingStats loops;
  std::vector<StampedPose> trajectory;
};

SlamOptions Options(bool loop_closing) {
  SlamOptions options;
  options.single_thread = true;
  options.loop.closing = loop_closing;
  return options;
}

LoopRun RunSynthetic(const SyntheticScene& scene, bool loop_closing) {
  Settings settings;
  settings.camera = scene.camera().intrinsics();
  SlamSystem system(settings, Options(loop_closing));
  LoopRun run;
  for (int i = 0; i < scene.num_frames(); ++i) {
    const SynthFrame frame = scene.RenderFrame(i);
    run.tracked += system.TrackRgbd(frame.bgr, frame.depth_m, frame.timestamp).has_pose;
    ++run.frames;
  }
  system.Shutdown();
  run.loops = system.loop_stats();
  run.trajectory = system.Trajectory();
  run.ate_rmse = ComputeAte(scene.GroundTruth(), run.trajectory).translation_m.rmse;
  return run;
}

LoopRun RunSequence(const std::string& dir, const std::string& settings_file, bool loop_closing) {
  const Settings settings = LoadSettings(std::string(ESDSLAM_SOURCE_DIR) + "/config/" + settings_file);
  const TumSequence sequence = TumSequence::Open(dir);
  SlamSystem system(settings, Options(loop_closing));
  LoopRun run;
  for (const FrameEntry& entry : sequence.frames()) {
    const RgbdImages images = LoadRgbd(entry, settings.depth_map_factor);
    run.tracked += system.TrackRgbd(images.bgr, images.depth_m, entry.timestamp).has_pose;
    ++run.frames;
  }
  system.Shutdown();
  run.loops = system.loop_stats();
  run.trajectory = system.Trajectory();
  run.ate_rmse = ComputeAte(ReadTumTrajectory(sequence.groundtruth_path()), run.trajectory).translation_m.rmse;
  return run;
}

void ExpectSameTrajectory(const std::vector<StampedPose>& a, const std::vector<StampedPose>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].world_from_cam.translation(), b[i].world_from_cam.translation()) << i;
    EXPECT_EQ(a[i].world_from_cam.rotation().coeffs(), b[i].world_from_cam.rotation().coeffs()) << i;
  }
}

void Print(const char* name, const LoopRun& on, const LoopRun& off) {
  std::printf("%s: loop closing on: %d/%d tracked, ATE %.4f m, %d keyframes checked, %d candidates verified, %d loops "
              "closed, %d global BA; off: %d/%d tracked, ATE %.4f m\n",
              name, on.tracked, on.frames, on.ate_rmse, on.loops.keyframes_checked, on.loops.consistent_candidates,
              on.loops.loops_closed, on.loops.global_ba.completed, off.tracked, off.frames, off.ate_rmse);
  for (const LoopEvent& event : on.loops.events)
    std::printf("  loop keyframe %ld -> %ld: %d inliers, %d matches, %d fused, correction %.3f m / %.2f deg\n",
                event.current_id, event.loop_id, event.inliers, event.matches, event.fused, event.correction_m,
                event.correction_deg);
}

TEST(LoopClosingSlowTest, SyntheticLoopIsClosedAndHalvesTheAte) {
  const SyntheticScene scene(SynthPreset("loop"));
  const LoopRun off = RunSynthetic(scene, false);
  const LoopRun on = RunSynthetic(scene, true);
  Print("synthetic loop", on, off);
  EXPECT_EQ(off.tracked, off.frames);
  EXPECT_EQ(on.tracked, on.frames);
  EXPECT_GE(on.loops.loops_closed, 1);
  EXPECT_EQ(on.loops.global_ba.completed, on.loops.loops_closed);
  ASSERT_FALSE(on.loops.events.empty());
  // The loop found is the real one: the current keyframe near the end, the loop keyframe near
  // the start of the turn.
  EXPECT_LE(on.ate_rmse, 0.5 * off.ate_rmse);
}

TEST(LoopClosingSlowTest, NoFalseLoopOnSyntheticSequencesWithoutRevisits) {
  for (const char* preset : {"static", "dynamic"}) {
    const SyntheticScene scene(SynthPreset(preset));
    const LoopRun on = RunSynthetic(scene, true);
    const LoopRun off = RunSynthetic(scene, false);
    Print(preset, on, off);
    EXPECT_EQ(on.loops.loops_closed, 0) << preset;
    EXPECT_GT(on.loops.keyframes_checked, 0) << preset;
    ExpectSameTrajectory(on.trajectory, off.trajectory);
  }
}

TEST(LoopClosingSlowTest, NoFalseLoopOnTheDevWindows) {
  const std::vector<std::pair<std::string, std::string>> windows{{"tum_fr1_rpy_dev", "tum_fr1.yaml"},
                                                                 {"bonn_crowd_dev", "bonn.yaml"}};
  for (const auto& [name, settings] : windows) {
    const std::string dir = kData + name;
    if (!std::filesystem::exists(dir)) {
      std::printf("%s not found: skipped\n", dir.c_str());
      continue;
    }
    const LoopRun on = RunSequence(dir, settings, true);
    const LoopRun off = RunSequence(dir, settings, false);
    Print(name.c_str(), on, off);
    EXPECT_EQ(on.loops.loops_closed, 0) << name;
    ExpectSameTrajectory(on.trajectory, off.trajectory);
  }
}

}  // namespace
}  // namespace esdslam
