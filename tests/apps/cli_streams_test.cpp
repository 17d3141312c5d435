// Output streams of `esdslam` (issue 14 item 4): log lines and errors on stderr, results on
// stdout; `eval --json` prints exactly one JSON document; `run` writes settings_used.yaml and
// logs one short line about it. Skipped when the program has not been built.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "support/program.h"
#include "support/temp_path.h"
#include "support/test_paths.h"

namespace esdslam {
namespace {

namespace fs = std::filesystem;

struct Streams {
  int exit_code = -1;
  std::string out, err;
};

class CliStreamsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(Program())) GTEST_SKIP() << "build the esdslam target first";
    dir_ = testing::TestTempPath("cli_streams");
    fs::create_directories(dir_);
  }
  static std::string Program() { return testing::EsdslamProgram(); }
  std::string Write(const std::string& name, const std::string& text) {
    const std::string path = dir_ + "/" + name;
    std::ofstream(path) << text;
    return path;
  }
  // Runs the program with stdout and stderr captured apart.
  Streams Run(const std::string& arguments) {
    const std::string out = dir_ + "/stdout.txt", err = dir_ + "/stderr.txt";
    const int status = std::system((Program() + " " + arguments + " >" + out + " 2>" + err).c_str());
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, testing::ReadTextFile(out), testing::ReadTextFile(err)};
  }
  std::string dir_;
};

// One JSON object: '{' first, its matching '}' last, nothing else (strings hold no braces here).
bool IsOneJsonObject(const std::string& text) {
  const auto begin = text.find_first_not_of(" \n");
  const auto end = text.find_last_not_of(" \n");
  if (begin == std::string::npos || text[begin] != '{' || text[end] != '}') return false;
  int depth = 0;
  for (std::size_t i = begin; i <= end; ++i) {
    if (text[i] == '{') ++depth;
    if (text[i] == '}' && --depth == 0 && i != end) return false;
  }
  return depth == 0;
}

TEST_F(CliStreamsTest, EvalJsonIsOneDocumentEvenWithAWarning) {
  // 0.3 s of poses: too short for the RPE over 1 s, which logs a warning.
  const std::string poses = "1.0 0 0 0 0 0 0 1\n1.1 0.1 0 0 0 0 0 1\n1.2 0.1 0.1 0 0 0 0 1\n1.3 0 0.1 0.05 0 0 0 1\n";
  const std::string truth = Write("truth.txt", poses);
  const std::string estimate = Write("estimate.txt", poses);
  const Streams r = Run("eval --json " + truth + " " + estimate);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(IsOneJsonObject(r.out)) << r.out;
  EXPECT_NE(r.out.find("\"ate_rmse\""), std::string::npos) << r.out;
}

TEST_F(CliStreamsTest, ErrorsGoToStderr) {
  const std::string estimate = Write("bad.txt", "1.0 0 0 zero 0 0 0 1\n");
  const Streams r = Run("eval " + estimate + " " + estimate);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_EQ(r.out, "");
  EXPECT_NE(r.err.find("bad.txt:1"), std::string::npos) << r.err;
}

TEST_F(CliStreamsTest, SettingsErrorsNameTheKeyAndLineOnStderr) {
  const std::string settings = Write("s.yaml", "%YAML:1.0\nCamera.fx: 500\nCamera.fy: 500\nCamera.cx: 320\n"
                                               "Camera.cy: 240\nDense.voxelSize: 1e-6\n");
  const Streams r = Run("run --settings " + settings + " --sequence " + dir_ + " --out " + dir_ + "/out");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_EQ(r.out, "");
  EXPECT_NE(r.err.find("s.yaml:6: Dense.voxelSize"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace esdslam
