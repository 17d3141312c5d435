// Loop closing end to end (single thread, so every run repeats exactly):
//   - the synthetic "orbit" preset (1.35 turns around the room centre with depth noise): the
//     loop is found between the start of the first turn and the revisit, closing it lowers the
//     ATE clearly (see docs/RESULTS.md for the figures and their seed dependence);
//   - sequences without revisits (synthetic static / dynamic presets, TUM fr1_rpy and Bonn crowd
//     dev windows): no loop is closed, and the trajectory is exactly the one of loop closing off.
#include <gtest/gtest.h>

#include <filesystem>

#include "eval/ate.h"
#include "io/settings.h"
#include "io/tum_sequence.h"
#include "synth/sequence_writer.h"
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

// settings_path: absolute, or relative to config/.
LoopRun RunSequence(const std::string& dir, const std::string& settings_path, bool loop_closing) {
  const bool absolute = !settings_path.empty() && settings_path.front() == '/';
  const Settings settings =
      LoadSettings(absolute ? settings_path : std::string(ESDSLAM_SOURCE_DIR) + "/config/" + settings_path);
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

// The orbit preset written once (rendering is the slow part), then run from disk twice.
const std::string& OrbitSequence() {
  static const std::string dir = [] {
    const std::string out = (std::filesystem::temp_directory_path() / "esdslam_loop_closing_orbit").string();
    std::filesystem::remove_all(out);
    WriteSynthSequence(SyntheticScene(SynthPreset("orbit")), out);
    return out;
  }();
  return dir;
}

TEST(LoopClosingSlowTest, SyntheticOrbitLoopIsClosedAndLowersTheAte) {
  const std::string dir = OrbitSequence();
  const LoopRun off = RunSequence(dir, dir + "/settings.yaml", false);
  const LoopRun on = RunSequence(dir, dir + "/settings.yaml", true);
  Print("synthetic orbit", on, off);
  EXPECT_EQ(off.tracked, off.frames);
  EXPECT_EQ(on.tracked, on.frames);
  EXPECT_EQ(off.loops.loops_closed, 0);
  ASSERT_EQ(on.loops.loops_closed, 1);  // the revisit is one place: one loop, then map reuse
  EXPECT_EQ(on.loops.global_ba.completed, 1);
  // The loop found is the real one: a keyframe of the revisit (after one turn, 450 of 607
  // frames) back to the first keyframes.
  const LoopEvent& loop = on.loops.events.front();
  const double turn_end = 100.0 + 449 / 30.0;  // timestamp of the first frame of the revisit
  EXPECT_GT(loop.timestamp, turn_end);
  EXPECT_LE(loop.loop_id, 5);
  EXPECT_GT(loop.correction_m, 0.005);  // there was drift to correct
  // Closing the loop lowers the ATE markedly; the target is half. Measured on the
  // default seed 0.42 (0.0040 vs 0.0095 m); seeds 2 and 3: 0.70 and 0.47 (docs/RESULTS.md).
  EXPECT_LE(on.ate_rmse, 0.5 * off.ate_rmse);
}

TEST(LoopClosingSlowTest, NoFalseLoopOnSyntheticSequencesWithoutRevisits) {
  for (const char* preset : {"static", "dynamic"}) {
    const SyntheticScene scene(SynthPreset(preset));
    const LoopRun on = RunSynthetic(scene, true);
    std::printf("%s: %d/%d tracked, ATE %.4f m, %d keyframes checked, %d candidates verified, %d loops closed\n",
                preset, on.tracked, on.frames, on.ate_rmse, on.loops.keyframes_checked,
                on.loops.consistent_candidates, on.loops.loops_closed);
    EXPECT_EQ(on.loops.loops_closed, 0) << preset;
    EXPECT_GT(on.loops.keyframes_checked, 10) << preset;  // detection ran
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
