#include "io/append_file.h"

#include <sys/resource.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "common/error.h"
#include "io/test_files.h"
#include "io/trajectory_io.h"

namespace esdslam {
namespace {

using testing::TempDir;

std::string ReadAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// A soft RLIMIT_FSIZE for this (test) process while in scope, SIGXFSZ ignored as `esdslam` does.
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    ::getrlimit(RLIMIT_FSIZE, &saved_);
    previous_handler_ = std::signal(SIGXFSZ, SIG_IGN);
    rlimit limit = saved_;
    limit.rlim_cur = bytes;
    ::setrlimit(RLIMIT_FSIZE, &limit);
  }
  ~FileSizeLimit() {
    ::setrlimit(RLIMIT_FSIZE, &saved_);
    std::signal(SIGXFSZ, previous_handler_);
  }

 private:
  rlimit saved_{};
  void (*previous_handler_)(int) = SIG_DFL;
};

TEST(AppendFileTest, EveryAppendIsOnDiskWhenItReturns) {
  TempDir dir;
  AppendFile file(dir.Path("a.txt"));
  file.Append("one\n");
  EXPECT_EQ(ReadAll(dir.Path("a.txt")), "one\n");  // no buffer to flush
  file.Append("two\n");
  EXPECT_EQ(ReadAll(dir.Path("a.txt")), "one\ntwo\n");
  EXPECT_EQ(file.size(), 8);
  file.Close();
  EXPECT_THROW(file.Append("three\n"), Error);
}

TEST(AppendFileTest, AnUnwritableFolderIsAnErrorNamingTheFile) {
  TempDir dir;
  try {
    AppendFile file(dir.Path("missing/a.txt"));
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("missing/a.txt"), std::string::npos) << e.what();
  }
}

// Regression (issue 14): with `ulimit -f` the file was cut mid-line and the process killed.
TEST(AppendFileTest, AFileSizeLimitGivesANamedErrorAndTheFileEndsAtTheLastWholeAppend) {
  TempDir dir;
  const std::string path = dir.Path("limited.txt");
  AppendFile file(path);
  const std::string line = "0123456789012345678901234567890123456789\n";  // 41 bytes
  std::string error;
  {
    FileSizeLimit limit(1000);
    try {
      for (int i = 0; i < 100; ++i) file.Append(line);
    } catch (const Error& e) {
      error = e.what();
    }
  }
  EXPECT_NE(error.find("cannot write " + path), std::string::npos) << error;
  EXPECT_NE(error.find("File too large"), std::string::npos) << error;
  const std::string text = ReadAll(path);
  EXPECT_EQ(text.size(), (1000 / line.size()) * line.size());  // 24 whole lines, no part of the 25th
  EXPECT_EQ(static_cast<std::size_t>(file.size()), text.size());
}

// A trajectory that cannot be written whole leaves the file that was there.
TEST(AppendFileTest, ATrajectoryThatDoesNotFitLeavesThePreviousFile) {
  TempDir dir;
  const std::string path = dir.Path("trajectory.txt");
  WriteTumTrajectory(path, {{1.0, Rigid3::Identity()}});
  const std::string before = ReadAll(path);
  std::vector<StampedPose> many(200, StampedPose{});
  for (std::size_t i = 0; i < many.size(); ++i) many[i].timestamp = 2.0 + static_cast<double>(i);
  {
    FileSizeLimit limit(2000);
    EXPECT_THROW(WriteTumTrajectory(path, many), Error);
  }
  EXPECT_EQ(ReadAll(path), before);
  EXPECT_FALSE(std::filesystem::exists(path + ".partial"));
}

}  // namespace
}  // namespace esdslam
