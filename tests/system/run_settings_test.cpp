// One settings table for a run: every stage's keys, list values, unknown keys, round trip.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "common/error.h"
#include "system/run_settings.h"
#include "support/temp_path.h"

namespace esdslam {
namespace {

const char* kCore = "%YAML:1.0\nCamera.fx: 500\nCamera.fy: 501\nCamera.cx: 320\nCamera.cy: 240\n";

std::string WriteTemp(const std::string& name, const std::string& text) {
  const std::string path = testing::TestTempPath("run_settings_" + name, ".yaml");
  std::ofstream(path) << text;
  return path;
}

TEST(RunSettingsTest, BindsEveryStageInOneTable) {
  const std::string path = WriteTemp(
      "all", std::string(kCore) +
                 "ORBextractor.nFeatures: 1500\n"
                 "Semantic.segmenter: folder\nSemantic.maskFolder: /tmp\n"
                 "Semantic.dynamicClasses: [person, dog]\nSemantic.potentiallyDynamicClasses: \"chair\"\n"
                 "Semantic.realtime: 1\n"
                 "Dynamic.grow.absTolerance: 0.05\nDynamic.check.absThreshold: 0.12\n"
                 "Dynamic.check.grow.growthBand: 9\nDense.voxelSize: 0.02\nUnknown.key: 3\nViewer.x: 1\n");
  std::vector<std::string> warnings;
  const RunSettings run = LoadRunSettings(path, &warnings);
  EXPECT_EQ(run.core.camera.fy, 501);
  EXPECT_EQ(run.core.orb.num_features, 1500);
  EXPECT_EQ(run.semantic.kind, SemanticSettings::Kind::kFolder);
  EXPECT_EQ(run.semantic.folder.folder, "/tmp");
  EXPECT_EQ(run.semantic.groups.dynamic_classes, (std::vector<std::string>{"person", "dog"}));
  EXPECT_EQ(run.semantic.groups.potentially_dynamic_classes, (std::vector<std::string>{"chair"}));
  EXPECT_EQ(run.semantic.mode, SegmentationMode::kNewestWins);
  EXPECT_DOUBLE_EQ(run.region_growing.abs_tolerance_m, 0.05);
  EXPECT_DOUBLE_EQ(run.geometry.check.abs_threshold_m, 0.12);
  EXPECT_EQ(run.geometry.check.growing.growth_band_px, 9);
  EXPECT_DOUBLE_EQ(run.dense.voxel_size, 0.02);
  ASSERT_EQ(warnings.size(), 1u);  // only Unknown.key; Viewer.* is ignored silently
  EXPECT_NE(warnings[0].find("Unknown.key"), std::string::npos);
}

TEST(RunSettingsTest, DefaultsAndModelSizeFromName) {
  const RunSettings run = LoadRunSettings(WriteTemp("defaults", std::string(kCore) +
                                                                    "Semantic.model: some/net_256x192.onnx\n"));
  EXPECT_EQ(run.semantic.kind, SemanticSettings::Kind::kOnnx);
  EXPECT_EQ(run.semantic.onnx.input_width, 256);
  EXPECT_EQ(run.semantic.onnx.input_height, 192);
  EXPECT_EQ(run.semantic.mode, SegmentationMode::kEveryFrame);
  EXPECT_EQ(run.semantic.groups.dynamic_classes, (std::vector<std::string>{"person"}));
  EXPECT_DOUBLE_EQ(run.region_growing.abs_tolerance_m, RegionGrowingOptions().abs_tolerance_m);
}

TEST(RunSettingsTest, SaveLoadRoundTripKeepsEveryValue) {
  RunSettings run = LoadRunSettings(WriteTemp("rt", std::string(kCore) + "Semantic.segmenter: folder\n"
                                                                          "Semantic.maskFolder: /tmp\n"));
  run.region_growing.depth_sq_tolerance = 0.0123456789;
  run.geometry.check.max_parallax_deg = 25;
  run.dense.pixel_stride = 3;
  run.semantic.groups.dynamic_classes = {"person", "cat"};
  run.semantic.groups.potentially_dynamic_classes = {"chair"};
  const std::string saved = testing::TestTempPath("run_settings_saved", ".yaml");
  SaveRunSettings(run, saved);
  std::vector<std::string> warnings;
  const RunSettings back = LoadRunSettings(saved, &warnings);
  EXPECT_TRUE(warnings.empty());
  EXPECT_EQ(RunSettingsYaml(back), RunSettingsYaml(run));
  EXPECT_DOUBLE_EQ(back.region_growing.depth_sq_tolerance, 0.0123456789);
  EXPECT_EQ(back.semantic.groups.dynamic_classes, run.semantic.groups.dynamic_classes);
}

TEST(RunSettingsTest, RejectsBadValuesWithInputError) {
  EXPECT_THROW(LoadRunSettings(WriteTemp("type", std::string(kCore) + "Dynamic.grow.seedErosion: abc\n")), InputError);
  EXPECT_THROW(LoadRunSettings(WriteTemp("seg", std::string(kCore) + "Semantic.segmenter: magic\n")), InputError);
  EXPECT_THROW(LoadRunSettings(WriteTemp("cls", std::string(kCore) + "Semantic.dynamicClasses: [person, unicorn]\n")),
               InputError);
  EXPECT_THROW(LoadRunSettings(WriteTemp("chk", std::string(kCore) + "Dense.voxelSize: -1\n")), InputError);
}

}  // namespace
}  // namespace esdslam
