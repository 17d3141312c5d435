// The run's one configuration: flags override the settings file, derived values are made once
// in ResolveRunConfig, Check() rejects bad values and disagreeing parts, and the constructors
// take the configuration as it is.
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "common/error.h"
#include "support/temp_path.h"
#include "system/run_config.h"
#include "system/run_settings.h"
#include "system/slam_system.h"

namespace esdslam {
namespace {

// loop: the Loop.* lines (default: relocalization and loop closing off, no vocabulary needed).
RunSettings SettingsFrom(const std::string& name, const std::string& extra,
                         const std::string& loop = "Loop.relocalization: 0\nLoop.closing: 0\n") {
  const std::string path = testing::TestTempPath("run_config_" + name, ".yaml");
  std::ofstream(path) << "%YAML:1.0\nCamera.fx: 500\nCamera.fy: 500\nCamera.cx: 320\nCamera.cy: 240\n"
                      << loop << extra;
  return LoadRunSettings(path);
}

TEST(RunConfigTest, FlagsOverrideTheSettingsFileOnce) {
  const RunSettings file = SettingsFrom("override", "Semantic.realtime: 0\nCamera.fps: 15\n",
                                        "Loop.relocalization: 1\nLoop.closing: 1\n");
  EXPECT_TRUE(file.loop.closing);
  RunFlags flags;
  flags.no_loop = true;
  flags.no_relocalization = true;
  flags.realtime = true;
  const RunConfig config = ResolveRunConfig(file, flags);
  // The settings keys record the override (settings_used.yaml is written from them) ...
  EXPECT_FALSE(config.settings.loop.closing);
  EXPECT_FALSE(config.settings.loop.relocalization);
  EXPECT_EQ(config.settings.semantic.mode, SegmentationMode::kNewestWins);
  // ... and the SLAM options are the same values; the keyframe interval follows Camera.fps.
  EXPECT_FALSE(config.slam.loop.closing);
  EXPECT_FALSE(config.slam.loop.relocalization);
  EXPECT_EQ(config.slam.tracker.max_frames_between_keyframes, 15);
  // Without flags the file's values stay.
  const RunConfig plain = ResolveRunConfig(SettingsFrom("plain", "Semantic.realtime: 1\n"), RunFlags{});
  EXPECT_EQ(plain.settings.semantic.mode, SegmentationMode::kNewestWins);
  EXPECT_EQ(plain.slam.tracker.max_frames_between_keyframes, 30);
  EXPECT_EQ(MaxFramesBetweenKeyframes(0.4), 1);
}

// Labels every 4th frame by default, with the smaller network on one OpenCV thread; every-frame
// labels (--segment-every 1) take the larger one; a model or thread count given stays.
TEST(RunConfigTest, LabelScheduleChoosesTheModelWhenNotGiven) {
  const RunSettings file = SettingsFrom("schedule", "");
  RunConfig config = ResolveRunConfig(file, RunFlags{});
  EXPECT_EQ(config.settings.semantic.segment_every, 4);
  EXPECT_EQ(config.settings.semantic.label_delay_frames, 0);
  EXPECT_EQ(config.pipeline.look_ahead_frames, 8);  // a recorded sequence is read ahead for the network
  EXPECT_EQ(config.settings.semantic.onnx.input_width, 256);
  EXPECT_EQ(config.settings.semantic.onnx.threads, 1);
  RunFlags live;
  live.run.live = true;
  EXPECT_EQ(ResolveRunConfig(file, live).pipeline.look_ahead_frames, 1);  // a camera's frames cannot be
  RunFlags realtime;
  realtime.realtime = true;
  EXPECT_EQ(ResolveRunConfig(file, realtime).pipeline.look_ahead_frames, 1);
  RunFlags none;
  none.mode = DynamicMode::kNone;
  EXPECT_EQ(ResolveRunConfig(file, none).pipeline.look_ahead_frames, 1);
  EXPECT_EQ(ResolveRunConfig(SettingsFrom("look_ahead", "Semantic.lookAhead: 7\n"), RunFlags{}).pipeline.look_ahead_frames, 7);
  EXPECT_THROW(SettingsFrom("look_ahead_bad", "Semantic.lookAhead: 0\n"), InputError);
  RunFlags every;
  every.segment_every = 1;
  config = ResolveRunConfig(file, every);
  EXPECT_EQ(config.pipeline.look_ahead_frames, 1);
  EXPECT_EQ(config.settings.semantic.segment_every, 1);
  EXPECT_EQ(config.settings.semantic.onnx.input_width, 384);
  EXPECT_EQ(config.settings.semantic.onnx.threads, 0);
  const RunSettings given =
      SettingsFrom("schedule_given", "Semantic.segmentEvery: 6\nSemantic.labelDelay: 1\nSemantic.threads: 2\n"
                                     "Semantic.model: models/espnetv2_s2.0_voc_384x288.onnx\n");
  config = ResolveRunConfig(given, RunFlags{});
  EXPECT_EQ(config.settings.semantic.segment_every, 6);
  EXPECT_EQ(config.settings.semantic.label_delay_frames, 1);
  EXPECT_EQ(config.settings.semantic.onnx.input_width, 384);
  EXPECT_EQ(config.settings.semantic.onnx.threads, 2);
  EXPECT_THROW(SettingsFrom("schedule_bad", "Semantic.segmentEvery: 0\n"), InputError);
}

TEST(RunConfigTest, ModeAndThreadsDecideTheDerivedOptions) {
  const RunSettings file = SettingsFrom("mode", "Dynamic.check.absThreshold: 0.2\n");
  RunFlags flags;
  flags.mode = DynamicMode::kGeometry;
  flags.single_thread = true;
  flags.dense = true;
  flags.run.out_dir = "/tmp/out";
  RunConfig config = ResolveRunConfig(file, flags);
  EXPECT_TRUE(config.slam.geometry_check);
  EXPECT_DOUBLE_EQ(config.slam.geometry.check.abs_threshold_m, 0.2);
  EXPECT_TRUE(config.slam.frame.mask_extraction);  // a caller's mask steers extraction in every mode
  EXPECT_TRUE(config.slam.single_thread);
  EXPECT_FALSE(config.pipeline.threaded_dense);
  EXPECT_EQ(config.pipeline.dense_mask_dir, "/tmp/out/masks");
  flags.mode = DynamicMode::kSemantic;
  flags.single_thread = false;
  config = ResolveRunConfig(file, flags);
  EXPECT_FALSE(config.slam.geometry_check);
  EXPECT_TRUE(config.slam.frame.mask_extraction);
  EXPECT_TRUE(config.pipeline.threaded_dense);
  flags.mask_extraction = false;
  EXPECT_FALSE(ResolveRunConfig(file, flags).slam.frame.mask_extraction);
  EXPECT_EQ(ParseDynamicMode("full"), DynamicMode::kFull);
  EXPECT_THROW(ParseDynamicMode("everything"), Error);
}

TEST(RunConfigTest, CheckRejectsOutOfRangeValuesAndDisagreeingParts) {
  const RunSettings file = SettingsFrom("check", "");
  RunFlags flags;
  flags.run.max_frames = -1;
  EXPECT_THROW(ResolveRunConfig(file, flags), Error);
  flags = {};
  flags.localization = true;  // needs a map to load
  EXPECT_THROW(ResolveRunConfig(file, flags), Error);
  RunSettings bad = file;
  bad.mask_refine.dilation_px = -1;
  EXPECT_THROW(ResolveRunConfig(bad, RunFlags{}), Error);
  bad = file;
  bad.mask_refine.scale = 0;
  EXPECT_THROW(ResolveRunConfig(bad, RunFlags{}), Error);

  const RunConfig good = ResolveRunConfig(file, RunFlags{});
  EXPECT_NO_THROW(good.Check());
  RunConfig changed = good;
  changed.slam.loop.closer.consistency_threshold += 1;  // Loop.consistency no longer what is recorded
  EXPECT_THROW(changed.Check(), Error);
  changed = good;
  changed.slam.geometry.check.abs_threshold_m *= 2;
  EXPECT_THROW(changed.Check(), Error);
  changed = good;
  changed.slam.tracker.max_frames_between_keyframes = 7;  // not Camera.fps
  EXPECT_THROW(changed.Check(), Error);
  changed = good;
  changed.slam.geometry_check = false;  // mode full runs it
  EXPECT_THROW(changed.Check(), Error);
  changed = good;
  changed.pipeline.dense_mask_dir = "/tmp/masks";  // without the dense map
  EXPECT_THROW(changed.Check(), Error);
  PipelineOptions pipeline;
  pipeline.mode = static_cast<DynamicMode>(9);
  EXPECT_THROW(pipeline.Check(), Error);
}

TEST(RunConfigTest, TheSlamSystemTakesItsOptionsAsTheyAre) {
  const RunConfig config = ResolveRunConfig(SettingsFrom("system", "Camera.fps: 10\n"), RunFlags{});
  SlamOptions options = config.slam;
  options.tracker.max_frames_between_keyframes = 4;  // Camera.fps would say 10
  const SlamSystem system(config.settings.core, options);
  EXPECT_EQ(system.options().tracker.max_frames_between_keyframes, 4);
}

}  // namespace
}  // namespace esdslam
