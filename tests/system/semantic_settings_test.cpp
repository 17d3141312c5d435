#include "system/run_settings.h"

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <unistd.h>

#include "common/error.h"

namespace esdslam {
namespace {
namespace fs = std::filesystem;

class SemanticSettingsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("esdslam_sem_settings_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string Write(const std::string& text) {
    const std::string path = (dir_ / "settings.yaml").string();
    std::ofstream(path) << text;
    return path;
  }
  fs::path dir_;
};

TEST_F(SemanticSettingsTest, ReadsOrbSlamStyleFileWithYamlDirective) {
  const std::string path = Write(
      "%YAML:1.0\n"
      "Camera.fx: 542.822841\n"
      "Semantic.model: \"models/espnetv2_s2.0_voc_256x192.onnx\"\n"
      "Semantic.threads: 2\n"
      "Semantic.dynamicClasses: [person, dog]\n"
      "Semantic.potentiallyDynamicClasses: \"chair, bottle\"\n"
      "Semantic.realtime: 1\n");
  const SemanticSettings s = LoadSemanticSettings(path);
  EXPECT_EQ(s.kind, SemanticSettings::Kind::kOnnx);
  EXPECT_EQ(s.onnx.input_width, 256);  // from the model name
  EXPECT_EQ(s.onnx.input_height, 192);
  EXPECT_EQ(s.onnx.threads, 2);
  EXPECT_EQ(s.groups.dynamic_classes, (std::vector<std::string>{"person", "dog"}));
  EXPECT_EQ(s.groups.potentially_dynamic_classes, (std::vector<std::string>{"chair", "bottle"}));
  EXPECT_EQ(s.mode, SegmentationMode::kNewestWins);
  // Resolved against the source tree: the shipped model exists.
  EXPECT_TRUE(fs::exists(s.onnx.model_path)) << s.onnx.model_path;
}

TEST_F(SemanticSettingsTest, ExplicitInputSizeWinsOverTheModelName) {
  const SemanticSettings s = LoadSemanticSettings(Write(
      "Semantic.model: other_320x224.onnx\nSemantic.inputWidth: 256\nSemantic.inputHeight: 192\n"));
  EXPECT_EQ(s.onnx.input_width, 256);
  EXPECT_EQ(s.onnx.input_height, 192);
}

TEST_F(SemanticSettingsTest, DefaultsFindTheShippedModel) {
  const SemanticSettings s = LoadSemanticSettings("");
  EXPECT_TRUE(fs::exists(s.onnx.model_path)) << s.onnx.model_path;
  EXPECT_EQ(s.onnx.input_width, 384);
  EXPECT_EQ(s.onnx.input_height, 288);
  EXPECT_EQ(s.groups.dynamic_classes, std::vector<std::string>{"person"});
  EXPECT_EQ(s.mode, SegmentationMode::kEveryFrame);
}

TEST_F(SemanticSettingsTest, FolderSegmenterKeys) {
  const SemanticSettings s = LoadSemanticSettings(Write(
      "Semantic.segmenter: folder\nSemantic.maskFolder: /data/masks\nSemantic.maskTolerance: 0.005\n"
      "Semantic.allowMissingMasks: 1\n"));
  EXPECT_EQ(s.kind, SemanticSettings::Kind::kFolder);
  EXPECT_EQ(s.folder.folder, "/data/masks");
  EXPECT_DOUBLE_EQ(s.folder.tolerance_s, 0.005);
  EXPECT_TRUE(s.folder.allow_missing);
}

TEST_F(SemanticSettingsTest, BadValuesAreInputErrorsWithTheLine) {
  try {
    LoadSemanticSettings(Write("%YAML:1.0\nSemantic.threads: 1\nSemantic.inputWidth: wide\n"));
    FAIL() << "expected an error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 3);
  }
  EXPECT_THROW(LoadSemanticSettings(Write("Semantic.inputWidth: 100\n")), InputError);  // not /32
  EXPECT_THROW(LoadSemanticSettings(Write("Semantic.dynamicClasses: [pedestrian]\n")), InputError);
  EXPECT_THROW(LoadSemanticSettings(Write("Semantic.segmenter: magic\n")), InputError);
  EXPECT_THROW(LoadSemanticSettings((dir_ / "absent.yaml").string()), InputError);
}

}  // namespace
}  // namespace esdslam
