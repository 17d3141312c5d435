// ORB-SLAM2 and ORB-SLAM3 files read unchanged (issue 14 item 5): the example settings (copies in
// tests/data/orbslam, the users' copies in ../shared/data/orbslam_files) and the 4-column
// association files of ORB-SLAM2's rgbd_tum.
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "common/error.h"
#include "io/settings.h"
#include "io/settings_table.h"
#include "io/test_files.h"
#include "io/tum_sequence.h"
#include "support/program.h"
#include "support/test_paths.h"

namespace esdslam {
namespace {

namespace fs = std::filesystem;
using testing::TempDir;

std::string DataFile(const std::string& name) { return ::esdslam::testing::SourceDir() + "/tests/data/orbslam/" + name; }

// `text` with line `line` (1-based) replaced by `replacement`.
std::string ReplaceLine(const std::string& text, int line, const std::string& replacement) {
  std::istringstream in(text);
  std::string out, current;
  for (int n = 1; std::getline(in, current); ++n) out += (n == line ? replacement : current) + "\n";
  return out;
}

int LineOf(const std::string& text, const std::string& prefix) {
  std::istringstream in(text);
  std::string current;
  for (int n = 1; std::getline(in, current); ++n) {
    if (current.rfind(prefix, 0) == 0) return n;
  }
  return 0;
}

InputError LoadError(const std::string& path) {
  try {
    LoadSettings(path);
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << path << " loaded without an error";
  return InputError(path, -1, "none");
}

TEST(OrbSlamFiles, NormalizeAddsTheSpaceOpenCvDoesNotNeed) {
  EXPECT_EQ(NormalizeOpenCvYaml("%YAML:1.0\nViewer.PointSize:2\nA: 1\n"), "\nViewer.PointSize: 2\nA: 1\n");
  EXPECT_EQ(NormalizeOpenCvYaml("  Nested.key:-3.5"), "  Nested.key: -3.5");
  // Values, comments and quoted text are left alone; the line count never changes.
  EXPECT_EQ(NormalizeOpenCvYaml("model: \"a:b\"\n# Note:this\nurl: http://x\n"),
            "model: \"a:b\"\n# Note:this\nurl: http://x\n");
  EXPECT_EQ(NormalizeOpenCvYaml("x:\n  - a:b\n"), "x:\n  - a:b\n");
}

TEST(OrbSlamFiles, Orbslam2ExampleSettingsLoadUnchanged) {
  struct Expected {
    const char* name;
    double fx, fy, k1, depth_factor;
  };
  for (const Expected& e : {Expected{"orbslam2_TUM1.yaml", 517.306408, 516.469215, 0.262383, 5000},
                            Expected{"orbslam2_TUM2.yaml", 520.908620, 521.007327, 0.231222, 5208},
                            Expected{"orbslam2_TUM3.yaml", 535.4, 539.2, 0.0, 5000}}) {
    std::vector<std::string> warnings;
    const Settings s = LoadSettings(DataFile(e.name), &warnings);
    EXPECT_TRUE(warnings.empty()) << e.name << ": " << (warnings.empty() ? "" : warnings[0]);
    EXPECT_DOUBLE_EQ(s.camera.fx, e.fx) << e.name;
    EXPECT_DOUBLE_EQ(s.camera.fy, e.fy) << e.name;
    EXPECT_DOUBLE_EQ(s.camera.k1, e.k1) << e.name;
    EXPECT_DOUBLE_EQ(s.fps, 30.0) << e.name;
    EXPECT_DOUBLE_EQ(s.bf, 40.0) << e.name;
    EXPECT_DOUBLE_EQ(s.depth_map_factor, e.depth_factor) << e.name;
    EXPECT_EQ(s.orb.num_features, 1000) << e.name;
  }
}

TEST(OrbSlamFiles, Orbslam3RgbdSettingsLoad) {
  std::vector<std::string> warnings;
  const Settings s = LoadSettings(DataFile("orbslam3_TUM1.yaml"), &warnings);
  EXPECT_TRUE(warnings.empty()) << (warnings.empty() ? "" : warnings[0]);
  EXPECT_DOUBLE_EQ(s.camera.fx, 517.306408);
  EXPECT_DOUBLE_EQ(s.camera.cy, 255.313989);
  EXPECT_DOUBLE_EQ(s.camera.k3, 1.163314);
  EXPECT_EQ(s.camera.width, 640);
  EXPECT_DOUBLE_EQ(s.bf, 0.07732 * 517.306408);  // Stereo.b (m) times fx
  EXPECT_DOUBLE_EQ(s.th_depth, 40.0);             // Stereo.ThDepth
  EXPECT_DOUBLE_EQ(s.depth_map_factor, 5000.0);   // RGBD.DepthMapFactor
  EXPECT_EQ(s.orb.num_features, 1000);
  // Saved in ORB-SLAM2's keys: loads back to the same values, without the ORB-SLAM3 forms.
  TempDir dir;
  SaveSettings(s, dir.Path("saved.yaml"));
  const std::string saved = testing::ReadTextFile(dir.Path("saved.yaml"));
  EXPECT_EQ(saved.find("Camera1."), std::string::npos) << saved;
  EXPECT_EQ(saved.find("Stereo.b"), std::string::npos) << saved;
  const Settings again = LoadSettings(dir.Path("saved.yaml"));
  EXPECT_DOUBLE_EQ(again.bf, s.bf);
  EXPECT_DOUBLE_EQ(again.camera.fx, s.camera.fx);
}

TEST(OrbSlamFiles, TheUsersCopiesAreTheTestedFiles) {
  const std::string shared = ::esdslam::testing::TestDataDir() + "/data/orbslam_files";
  if (!fs::is_directory(shared)) GTEST_SKIP() << shared << " not present";
  for (const char* name : {"orbslam2_TUM1.yaml", "orbslam2_TUM2.yaml", "orbslam2_TUM3.yaml", "orbslam3_TUM1.yaml",
                           "fr1_rpy_dev_associations.txt"}) {
    EXPECT_EQ(testing::ReadTextFile(shared + "/" + name), testing::ReadTextFile(DataFile(name))) << name;
  }
  for (const char* name : {"orbslam2_TUM1.yaml", "orbslam2_TUM2.yaml", "orbslam2_TUM3.yaml", "orbslam3_TUM1.yaml"}) {
    EXPECT_NO_THROW(LoadSettings(shared + "/" + name)) << name;
  }
}

TEST(OrbSlamFiles, ErrorsInTheExampleFilesNameTheirLine) {
  TempDir dir;
  const std::string tum1 = testing::ReadTextFile(DataFile("orbslam2_TUM1.yaml"));
  const int fy_line = LineOf(tum1, "Camera.fy:");
  ASSERT_GT(fy_line, 1);
  const InputError type = LoadError(dir.Write("type.yaml", ReplaceLine(tum1, fy_line, "Camera.fy:abc")));
  EXPECT_EQ(type.line(), fy_line) << type.what();
  EXPECT_NE(std::string(type.what()).find("Camera.fy"), std::string::npos) << type.what();

  const int factor_line = LineOf(tum1, "DepthMapFactor:");
  const InputError range = LoadError(dir.Write("range.yaml", ReplaceLine(tum1, factor_line, "DepthMapFactor:1e-9")));
  EXPECT_EQ(range.line(), factor_line) << range.what();
  EXPECT_NE(std::string(range.what()).find("DepthMapFactor"), std::string::npos) << range.what();

  const int point_line = LineOf(tum1, "Viewer.PointSize:");
  const InputError syntax = LoadError(dir.Write("syntax.yaml", ReplaceLine(tum1, point_line, "Viewer.PointSize: [2")));
  EXPECT_GE(syntax.line(), point_line) << syntax.what();

  const std::string tum3v = testing::ReadTextFile(DataFile("orbslam3_TUM1.yaml"));
  const int fx3 = LineOf(tum3v, "Camera1.fx:");
  const InputError range3 = LoadError(dir.Write("range3.yaml", ReplaceLine(tum3v, fx3, "Camera1.fx: -5")));
  EXPECT_EQ(range3.line(), fx3) << range3.what();
  EXPECT_NE(std::string(range3.what()).find("Camera.fx"), std::string::npos) << range3.what();
}

TEST(OrbSlamFiles, Orbslam3FormsThatContradictAreErrors) {
  TempDir dir;
  const std::string v3 = testing::ReadTextFile(DataFile("orbslam3_TUM1.yaml"));
  const InputError both = LoadError(dir.Write("both.yaml", v3 + "Camera.fx: 517.3\n"));
  EXPECT_NE(std::string(both.what()).find("Camera1.fx"), std::string::npos) << both.what();
  EXPECT_GT(both.line(), LineOf(v3, "Camera1.fx"));
  const InputError bf = LoadError(dir.Write("bf.yaml", v3 + "Camera.bf: 40\n"));
  EXPECT_EQ(bf.line(), LineOf(v3, "Stereo.b:")) << bf.what();
  const InputError type =
      LoadError(dir.Write("type.yaml", ReplaceLine(v3, LineOf(v3, "Camera.type:"), "Camera.type: \"KannalaBrandt8\"")));
  EXPECT_EQ(type.line(), LineOf(v3, "Camera.type:")) << type.what();
  EXPECT_NE(std::string(type.what()).find("PinHole"), std::string::npos) << type.what();
  const InputError version =
      LoadError(dir.Write("version.yaml", ReplaceLine(v3, LineOf(v3, "File.version:"), "File.version: \"2.0\"")));
  EXPECT_EQ(version.line(), LineOf(v3, "File.version:")) << version.what();
}

TEST(OrbSlamFiles, AssociationFileGivesTheSameFramesAsTheLists) {
  const std::string dir = ::esdslam::testing::TestDataDir() + "/data/tum_fr1_rpy_dev";
  if (!fs::is_directory(dir)) GTEST_SKIP() << dir << " not present";
  AssociationOptions options;
  options.association_file = DataFile("fr1_rpy_dev_associations.txt");
  const TumSequence from_file = TumSequence::Open(dir, options);
  const TumSequence from_lists = TumSequence::Open(dir);
  ASSERT_EQ(from_file.frames().size(), from_lists.frames().size());
  for (std::size_t i = 0; i < from_file.frames().size(); ++i) {
    EXPECT_EQ(from_file.frames()[i].rgb_path, from_lists.frames()[i].rgb_path) << i;
    EXPECT_EQ(from_file.frames()[i].depth_path, from_lists.frames()[i].depth_path) << i;
    EXPECT_DOUBLE_EQ(from_file.frames()[i].timestamp, from_lists.frames()[i].timestamp) << i;
  }
}

TEST(OrbSlamFiles, AnAssociationFileIsDetectedWhenTheListsAreMissing) {
  TempDir dir;
  dir.Write("rgb/1.0.png", "x");
  dir.Write("depth/1.01.png", "x");
  dir.Write("rgb/2.0.png", "x");
  dir.Write("depth/2.01.png", "x");
  dir.Write("associations.txt", "1.0 rgb/1.0.png 1.01 depth/1.01.png\n2.0 rgb/2.0.png 2.01 depth/2.01.png\n");
  EXPECT_EQ(DetectAssociationFile(dir.Path()), dir.Path("associations.txt"));
  const TumSequence sequence = TumSequence::Open(dir.Path());
  ASSERT_EQ(sequence.frames().size(), 2u);
  EXPECT_DOUBLE_EQ(sequence.frames()[1].depth_timestamp, 2.01);
  // With rgb.txt present the lists win; a 4-column rgb.txt gets an error that says what it is.
  dir.Write("rgb.txt", "1.0 rgb/1.0.png 1.01 depth/1.01.png\n");
  dir.Write("depth.txt", "1.01 depth/1.01.png\n");
  EXPECT_EQ(DetectAssociationFile(dir.Path()), "");
  try {
    TumSequence::Open(dir.Path());
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 1);
    EXPECT_NE(std::string(e.what()).find("--associations"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace esdslam
