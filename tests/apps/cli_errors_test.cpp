// The `esdslam` program on bad input: a non-zero exit and an error that names the file (and the
// line where there is one). Skipped when the program has not been built.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "support/program.h"
#include "support/temp_path.h"
#include "support/test_paths.h"

namespace esdslam {
namespace {

namespace fs = std::filesystem;

testing::ShellResult RunProgram(const std::string& arguments) {
  return testing::RunShell(testing::EsdslamProgram() + " " + arguments);
}

class CliErrorsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(testing::EsdslamProgram())) GTEST_SKIP() << "build the esdslam target first";
    dir_ = testing::TestTempPath("cli_errors");
    fs::create_directories(dir_);
  }
  std::string Write(const std::string& name, const std::string& text) {
    const std::string path = dir_ + "/" + name;
    std::ofstream(path) << text;
    return path;
  }
  const std::string settings_ = ::esdslam::testing::SourceDir() + "/config/tum_fr1.yaml";
  std::string dir_;
};

TEST_F(CliErrorsTest, RunOnAMissingSequenceFolderFails) {
  const testing::ShellResult r = RunProgram("run --settings " + settings_ + " --sequence " + dir_ + "/nowhere --out " + dir_ + "/out");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find(dir_ + "/nowhere"), std::string::npos) << r.output;
}

TEST_F(CliErrorsTest, RunOnAnEmptySequenceFails) {
  fs::create_directories(dir_ + "/empty");
  Write("empty/rgb.txt", "# timestamp filename\n");
  Write("empty/depth.txt", "# timestamp filename\n");
  const testing::ShellResult r = RunProgram("run --settings " + settings_ + " --sequence " + dir_ + "/empty --out " + dir_ + "/out");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("empty"), std::string::npos) << r.output;
}

TEST_F(CliErrorsTest, SettingsWithoutARequiredKeyFailNamingFileAndKey) {
  const std::string settings = Write("no_fx.yaml", "%YAML:1.0\nCamera.fy: 500.0\nCamera.cx: 320.0\nCamera.cy: 240.0\n");
  const testing::ShellResult r = RunProgram("run --settings " + settings + " --sequence " + dir_ + " --out " + dir_ + "/out");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("no_fx.yaml"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("Camera.fx"), std::string::npos) << r.output;
}

TEST_F(CliErrorsTest, EvalOfAMalformedTrajectoryFailsNamingFileAndLine) {
  const std::string truth = Write("truth.txt", "1.0 0 0 0 0 0 0 1\n2.0 0 0 0 0 0 0 1\n3.0 0 0 0 0 0 0 1\n");
  const std::string estimate = Write("estimate.txt", "1.0 0 0 0 0 0 0 1\n2.0 0 0 zero 0 0 0 1\n");
  const testing::ShellResult r = RunProgram("eval " + truth + " " + estimate);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("estimate.txt:2"), std::string::npos) << r.output;
}

TEST_F(CliErrorsTest, EvalOfATrajectoryWithNanFails) {
  const std::string truth = Write("truth.txt", "1.0 0 0 0 0 0 0 1\n2.0 0 0 0 0 0 0 1\n3.0 0 0 0 0 0 0 1\n");
  const std::string estimate = Write("nan.txt", "1.0 0 0 0 0 0 0 1\n2.0 nan 0 0 0 0 0 1\n");
  const testing::ShellResult r = RunProgram("eval " + truth + " " + estimate);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("nan.txt:2"), std::string::npos) << r.output;
}

TEST_F(CliErrorsTest, RunNeedsASequenceOrACamera) {
  const testing::ShellResult r = RunProgram("run --settings " + settings_ + " --out " + dir_ + "/out");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("--sequence DIR or --camera"), std::string::npos) << r.output;
}

// No camera is attached here or in CI: the run stops before anything is written, saying why.
TEST_F(CliErrorsTest, RunOnACameraWithNoDeviceAttachedFailsSayingSo) {
  const testing::ShellResult r = RunProgram("run --settings " + settings_ + " --camera --out " + dir_ + "/cam");
  EXPECT_NE(r.exit_code, 0);
  const bool explained = r.output.find("no OpenNI2 device attached") != std::string::npos ||
                         r.output.find("built without OpenNI2") != std::string::npos;
  EXPECT_TRUE(explained) << r.output;
  EXPECT_FALSE(fs::exists(dir_ + "/cam"));
  const testing::ShellResult missing = RunProgram("run --settings " + settings_ + " --camera " + dir_ + "/walk.oni --out " + dir_ + "/cam");
  EXPECT_NE(missing.exit_code, 0);
  EXPECT_NE(missing.output.find(dir_ + "/walk.oni"), std::string::npos) << missing.output;
}

}  // namespace
}  // namespace esdslam
