#include "io/settings.h"

#include <gtest/gtest.h>

#include "common/error.h"
#include "io/settings_table.h"
#include "io/test_files.h"
#include "support/test_paths.h"

namespace esdslam {
namespace {

using testing::TempDir;

const char kMinimal[] =
    "%YAML:1.0\n"
    "Camera.fx: 500.5\n"
    "Camera.fy: 501\n"
    "Camera.cx: 320\n"
    "Camera.cy: 240\n";

void ExpectLoadError(const std::string& path, int line, const std::string& fragment) {
  try {
    LoadSettings(path);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), path);
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST(Settings, MinimalFileUsesDefaults) {
  TempDir dir;
  const Settings settings = LoadSettings(dir.Write("s.yaml", kMinimal));
  EXPECT_DOUBLE_EQ(settings.camera.fx, 500.5);
  EXPECT_DOUBLE_EQ(settings.camera.fy, 501);
  EXPECT_EQ(settings.camera.width, 640);
  EXPECT_DOUBLE_EQ(settings.depth_map_factor, 5000);
  EXPECT_EQ(settings.orb.num_features, 1000);
  EXPECT_EQ(settings.rgb_order, 1);
}

TEST(Settings, ShippedConfigsLoad) {
  struct Expected {
    const char* name;
    double fx, k1;
    double readout_s;  // Kinect (fr1, fr2) rolling shutter; Xtion (fr3, Bonn) treated as global
  };
  for (const Expected& expected :
       {Expected{"tum_fr1", 517.306408, 0.262383, 0.02}, Expected{"tum_fr2", 520.908620, 0.231222, 0.02},
        Expected{"tum_fr3", 535.4, 0.0, 0.0}, Expected{"bonn", 542.822841, 0.039903, 0.0}}) {
    std::vector<std::string> warnings;
    const std::string path = ::esdslam::testing::SourceDir() + "/config/" + expected.name + ".yaml";
    const Settings settings = LoadSettings(path, &warnings);
    EXPECT_TRUE(warnings.empty()) << path;
    EXPECT_DOUBLE_EQ(settings.camera.fx, expected.fx) << path;
    EXPECT_DOUBLE_EQ(settings.camera.k1, expected.k1) << path;
    EXPECT_DOUBLE_EQ(settings.readout_time_s, expected.readout_s) << path;
    EXPECT_DOUBLE_EQ(settings.bf, 40);
    EXPECT_DOUBLE_EQ(settings.th_depth, 40);
    EXPECT_DOUBLE_EQ(settings.depth_map_factor, 5000);
    EXPECT_DOUBLE_EQ(settings.fps, 30);
    EXPECT_EQ(settings.rgb_order, 1);
    EXPECT_EQ(settings.orb.num_features, 1000);
    EXPECT_DOUBLE_EQ(settings.orb.scale_factor, 1.2);
    EXPECT_EQ(settings.orb.num_levels, 8);
    EXPECT_EQ(settings.orb.initial_fast_threshold, 20);
    EXPECT_EQ(settings.orb.min_fast_threshold, 7);
  }
}

TEST(Settings, SaveThenLoadIsEqual) {
  TempDir dir;
  Settings settings;
  settings.camera = {517.306408, 516.469215, 318.643040, 255.313989, 0.262383, -0.953104, -0.005358, 0.002628,
                     1.163314, 320, 240};
  settings.fps = 1.0 / 3.0;  // needs all 17 digits
  settings.depth_map_factor = 1000;
  settings.th_depth = 35.5;
  settings.bf = 40.123456789012345;
  settings.rgb_order = 0;
  settings.orb = {2000, 1.1, 6, 25, 5};
  const std::string path = dir.Path("out/settings_used.yaml");
  SaveSettings(settings, path);
  const Settings loaded = LoadSettings(path);
  const auto& a = settings.camera;
  const auto& b = loaded.camera;
  EXPECT_TRUE(a.fx == b.fx && a.fy == b.fy && a.cx == b.cx && a.cy == b.cy && a.k1 == b.k1 && a.k2 == b.k2 &&
              a.p1 == b.p1 && a.p2 == b.p2 && a.k3 == b.k3 && a.width == b.width && a.height == b.height);
  EXPECT_EQ(loaded.fps, settings.fps);
  EXPECT_EQ(loaded.depth_map_factor, settings.depth_map_factor);
  EXPECT_EQ(loaded.th_depth, settings.th_depth);
  EXPECT_EQ(loaded.bf, settings.bf);
  EXPECT_EQ(loaded.rgb_order, 0);
  EXPECT_EQ(loaded.orb.num_features, 2000);
  EXPECT_EQ(loaded.orb.scale_factor, 1.1);
  EXPECT_EQ(loaded.orb.num_levels, 6);
  EXPECT_EQ(loaded.orb.initial_fast_threshold, 25);
  EXPECT_EQ(loaded.orb.min_fast_threshold, 5);
}

TEST(Settings, UnknownKeyWarnsWithFileAndLineViewerIgnored) {
  TempDir dir;
  const std::string path =
      dir.Write("s.yaml", std::string(kMinimal) +
                              "Viewer.KeyFrameSize: 0.05\nCamera.fxx: 3\nViewer.ViewpointF: 500\n"
                              "LEFT.K: !!opencv-matrix\n  rows: 1\n  cols: 1\n  dt: d\n  data: [1.0]\n");
  std::vector<std::string> warnings;
  LoadSettings(path, &warnings);
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_EQ(warnings[0], path + ":7: unknown settings key 'Camera.fxx' (ignored)");
  EXPECT_EQ(warnings[1], path + ":9: unknown settings key 'LEFT.K' (ignored)");  // tagged map: one key
}

TEST(Settings, MissingRequiredKeyNamesFileAndKey) {
  TempDir dir;
  ExpectLoadError(dir.Write("s.yaml", "%YAML:1.0\nCamera.fx: 1\nCamera.fy: 1\nCamera.cx: 1\n"), 0, "Camera.cy");
}

TEST(Settings, WrongTypeNamesLine) {
  TempDir dir;
  ExpectLoadError(dir.Write("a.yaml", std::string(kMinimal) + "Camera.k1: abc\n"), 6, "expected real");
  ExpectLoadError(dir.Write("b.yaml", std::string(kMinimal) + "\nORBextractor.nLevels: 2.5\n"), 7, "expected integer");
  ExpectLoadError(dir.Write("c.yaml", std::string(kMinimal) + "Camera.k2: [1, 2]\n"), 6, "a list or map");
  ExpectLoadError(dir.Write("d.yaml", std::string(kMinimal) + "DepthMapFactor: .nan\n"), 6, "expected real");
  ExpectLoadError(dir.Write("e.yaml", std::string(kMinimal) + "Camera.k1:\n"), 6, "expected real, got no value");
}

TEST(Settings, IntegralRealAcceptedForIntegers) {
  TempDir dir;
  EXPECT_EQ(LoadSettings(dir.Write("s.yaml", std::string(kMinimal) + "Camera.width: 320.0\n")).camera.width, 320);
}

TEST(Settings, SyntaxErrorDuplicateAndFailedCheck) {
  TempDir dir;
  // The unclosed flow sequence is reported where the parser gives up: the end of the file (line 7).
  ExpectLoadError(dir.Write("a.yaml", std::string(kMinimal) + "Camera.k1: [1,\n"), 7, "YAML syntax error");
  ExpectLoadError(dir.Write("b.yaml", std::string(kMinimal) + "Camera.fx: 2\n"), 6, "duplicate key");
  // A failed range check is reported at the line of its key.
  ExpectLoadError(dir.Write("c.yaml", std::string(kMinimal) + "Camera.RGB: 2\n"), 6, "Camera.RGB");
  ExpectLoadError(dir.Write("d.yaml", std::string(kMinimal) + "ORBextractor.scaleFactor: 1.0\n"), 6, "scaleFactor");
  ExpectLoadError(dir.Path("none.yaml"), 0, "not found");
}

TEST(Settings, RollingShutterReadoutIsBoundedByTheFramePeriod) {
  TempDir dir;
  EXPECT_DOUBLE_EQ(LoadSettings(dir.Write("a.yaml", kMinimal)).readout_time_s, 0.0);  // global shutter
  EXPECT_DOUBLE_EQ(LoadSettings(dir.Write("b.yaml", std::string(kMinimal) + "Camera.readoutTime: 0.02\n")).readout_time_s,
                   0.02);
  ExpectLoadError(dir.Write("c.yaml", std::string(kMinimal) + "Camera.readoutTime: -0.01\n"), 6, "Camera.readoutTime");
  // 0.04 s is more than a 30 Hz frame period.
  ExpectLoadError(dir.Write("d.yaml", std::string(kMinimal) + "Camera.readoutTime: 0.04\n"), 6, "Camera.readoutTime");
  EXPECT_DOUBLE_EQ(
      LoadSettings(dir.Write("e.yaml", std::string(kMinimal) + "Camera.fps: 20\nCamera.readoutTime: 0.04\n")).readout_time_s,
      0.04);
}

TEST(Settings, NestedMapsAreDottedKeys) {
  TempDir dir;
  const Settings settings =
      LoadSettings(dir.Write("s.yaml", "Camera:\n  fx: 10\n  fy: 11\n  cx: 5\n  cy: 6\nORBextractor: {nLevels: 4}\n"));
  EXPECT_DOUBLE_EQ(settings.camera.fy, 11);
  EXPECT_EQ(settings.orb.num_levels, 4);
}

TEST(SettingsTable, OtherStagesBindTheirOwnKeys) {
  struct StageOptions {
    bool enabled = false;
    std::string model = "none";
    double radius = 1;
  } stage;
  Settings core;
  SettingsTable table;
  BindCoreSettings(core, table);
  table.Add("Stage.enabled", &stage.enabled);
  table.Add("Stage.model", &stage.model, SettingsTable::Need::kRequired);
  table.Add("Stage.radius", &stage.radius);
  EXPECT_THROW(table.Add("Stage.radius", &stage.radius), Error);  // bound twice
  const auto warnings = table.LoadFromString(
      std::string(kMinimal) + "Stage.enabled: true\nStage.model: \"models/a b.onnx\"\n", "mem.yaml");
  EXPECT_TRUE(warnings.empty());
  EXPECT_TRUE(stage.enabled);
  EXPECT_EQ(stage.model, "models/a b.onnx");
  EXPECT_DOUBLE_EQ(core.camera.fx, 500.5);
  // Round trip through text keeps the string and the boolean.
  StageOptions copy;
  Settings core_copy;
  SettingsTable copy_table;
  BindCoreSettings(core_copy, copy_table);
  copy_table.Add("Stage.enabled", &copy.enabled);
  copy_table.Add("Stage.model", &copy.model);
  copy_table.Add("Stage.radius", &copy.radius);
  copy_table.LoadFromString(table.ToYaml(), "copy.yaml");
  EXPECT_TRUE(copy.enabled);
  EXPECT_EQ(copy.model, stage.model);
  // A missing required key of another stage is reported like a core one.
  try {
    Settings other;
    StageOptions other_stage;
    SettingsTable other_table;
    BindCoreSettings(other, other_table);
    other_table.Add("Stage.model", &other_stage.model, SettingsTable::Need::kRequired);
    other_table.LoadFromString(kMinimal, "mem.yaml");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("Stage.model"), std::string::npos);
  }
}

}  // namespace
}  // namespace esdslam
