// `esdslam run` stopped or fed bad input (issue 14): a signal, a file-size limit, corrupt and
// all-zero-depth frames, images of the wrong size. Each test writes a short synthetic sequence
// with `esdslam synth` and runs the built program in a child process. Skipped when the program
// has not been built.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "support/program.h"
#include "support/temp_path.h"
#include "synth/sequence_writer.h"
#include "synth/synthetic_scene.h"
#include "support/test_paths.h"

namespace esdslam {
namespace {

namespace fs = std::filesystem;

std::string Program() { return testing::EsdslamProgram(); }

// The program as a child process, stdout and stderr into one pipe.
class Child {
 public:
  // file_size_limit: RLIMIT_FSIZE in bytes for the child (0 = none).
  explicit Child(const std::vector<std::string>& args, rlim_t file_size_limit = 0) {
    int fds[2];
    if (::pipe(fds) != 0) return;
    pid_ = ::fork();
    if (pid_ == 0) {
      ::dup2(fds[1], STDOUT_FILENO);
      ::dup2(fds[1], STDERR_FILENO);
      ::close(fds[0]);
      ::close(fds[1]);
      if (file_size_limit > 0) {
        const rlimit limit{file_size_limit, file_size_limit};
        ::setrlimit(RLIMIT_FSIZE, &limit);
      }
      std::vector<char*> argv;
      const std::string program = Program();
      argv.push_back(const_cast<char*>(program.c_str()));
      for (const std::string& arg : args) argv.push_back(const_cast<char*>(arg.c_str()));
      argv.push_back(nullptr);
      ::execv(argv[0], argv.data());
      ::_exit(127);
    }
    ::close(fds[1]);
    fd_ = fds[0];
  }
  ~Child() {
    if (fd_ >= 0) ::close(fd_);
    if (pid_ > 0 && !waited_) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, nullptr, 0);
    }
  }
  // Reads the output until `text` appears in it (true) or the output ends (false).
  bool ReadUntil(const std::string& text) {
    while (output_.find(text) == std::string::npos) {
      if (!ReadSome()) return false;
    }
    return true;
  }
  void Signal(int signal_number) { ::kill(pid_, signal_number); }
  // Reads the rest of the output and waits; the exit status (128 + signal when killed by one).
  int Wait() {
    while (ReadSome()) {
    }
    int status = 0;
    ::waitpid(pid_, &status, 0);
    waited_ = true;
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  }
  const std::string& output() const { return output_; }

 private:
  bool ReadSome() {
    char buffer[4096];
    const ssize_t n = ::read(fd_, buffer, sizeof(buffer));
    if (n <= 0) return false;
    output_.append(buffer, static_cast<std::size_t>(n));
    return true;
  }
  pid_t pid_ = -1;
  int fd_ = -1;
  bool waited_ = false;
  std::string output_;
};

int RunToEnd(const std::vector<std::string>& args, std::string* output, rlim_t file_size_limit = 0) {
  Child child(args, file_size_limit);
  const int status = child.Wait();
  *output = child.output();
  return status;
}

std::vector<std::string> ReadLines(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

int PoseLines(const std::string& path) {
  int n = 0;
  for (const std::string& line : ReadLines(path)) n += !line.empty() && line[0] != '#';
  return n;
}

// Waits until the running child's trajectory.txt holds n poses (true), or gives up after two
// minutes (false). The file grows by whole lines after every frame.
bool WaitForPoseLines(const std::string& path, int n) {
  for (int i = 0; i < 2400; ++i) {
    if (PoseLines(path) >= n) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return false;
}

// "frames_tracked X / Y (processed Z)" of the summary; -1 when missing.
int SummaryValue(const std::string& output, const std::string& pattern) {
  std::smatch match;
  if (!std::regex_search(output, match, std::regex(pattern))) return -1;
  return std::stoi(match[1].str());
}

class RunReliabilityTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(Program())) GTEST_SKIP() << "build the esdslam target first";
    dir_ = testing::TestTempPath("run_reliability");
    fs::create_directories(dir_);
  }
  // A static synthetic sequence of `frames` frames in dir_/seq (as `esdslam synth --preset
  // static` writes it, without supersampling to be quick).
  std::string Synth(int frames) {
    SynthOptions options = SynthPreset("static");
    options.num_frames = frames;
    options.supersampling = 1;
    const std::string seq = dir_ + "/seq";
    WriteSynthSequence(SyntheticScene(options), seq);
    return seq;
  }
  std::vector<std::string> RunArgs(const std::string& seq, const std::string& settings = "") const {
    return {"run", "--settings", settings.empty() ? seq + "/settings.yaml" : settings, "--sequence", seq,
            "--out", out_, "--mode", "none"};
  }
  // The listed file names of DIR/rgb.txt or depth.txt, in order.
  static std::vector<std::string> Listed(const std::string& seq, const std::string& list) {
    std::vector<std::string> files;
    for (const std::string& line : ReadLines(seq + "/" + list)) {
      if (line.empty() || line[0] == '#') continue;
      std::istringstream fields(line);
      std::string stamp, file;
      fields >> stamp >> file;
      files.push_back(seq + "/" + file);
    }
    return files;
  }
  int Eval(const std::string& seq) const {
    std::string output;
    const int status = RunToEnd({"eval", seq + "/groundtruth.txt", out_ + "/trajectory.txt"}, &output);
    EXPECT_EQ(status, 0) << output;
    return status;
  }
  std::string dir_;
  std::string out_ = testing::TestTempPath("run_reliability_out");
};

class StopSignalTest : public RunReliabilityTest, public ::testing::WithParamInterface<int> {};

// Ctrl-C / SIGTERM after the map initialised: the run stops after the current frame, writes
// every output, and trajectory.txt holds every frame tracked (the summary's count) and evaluates.
TEST_P(StopSignalTest, StopsAfterTheCurrentFrameWithEveryOutputWritten) {
  const int frames = 40;
  const std::string seq = Synth(frames);
  Child child(RunArgs(seq));
  ASSERT_TRUE(WaitForPoseLines(out_ + "/trajectory.txt", 5));
  child.Signal(GetParam());
  const int status = child.Wait();
  const std::string& output = child.output();
  EXPECT_EQ(status, 128 + GetParam()) << output;
  EXPECT_NE(output.find("stopped by signal"), std::string::npos) << output;
  const int tracked = SummaryValue(output, R"(frames_tracked (\d+) /)");
  const int processed = SummaryValue(output, R"(\(processed (\d+)\))");
  ASSERT_GE(tracked, 1) << output;
  EXPECT_LT(processed, frames) << output;  // stopped early
  EXPECT_EQ(PoseLines(out_ + "/trajectory.txt"), tracked);
  EXPECT_EQ(static_cast<int>(ReadLines(out_ + "/timing.csv").size()), processed + 1);  // header + a row per frame
  EXPECT_GE(PoseLines(out_ + "/keyframes.txt"), 1);
  EXPECT_TRUE(fs::exists(out_ + "/settings_used.yaml"));
  Eval(seq);
}

INSTANTIATE_TEST_SUITE_P(Signals, StopSignalTest, ::testing::Values(SIGINT, SIGTERM));

// A second signal exits at once, with the files as they are on disk: whole lines only.
TEST_F(RunReliabilityTest, ASecondSignalExitsAtOnce) {
  const std::string seq = Synth(40);
  Child child(RunArgs(seq));
  ASSERT_TRUE(child.ReadUntil("map initialised")) << child.output();
  child.Signal(SIGINT);
  ASSERT_TRUE(child.ReadUntil("signal again to quit at once")) << child.output();
  child.Signal(SIGINT);
  EXPECT_EQ(child.Wait(), 128 + SIGINT) << child.output();
  for (const std::string name : {"trajectory.txt", "timing.csv"}) {
    std::ifstream in(out_ + "/" + name, std::ios::binary);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ASSERT_FALSE(text.empty()) << name;
    EXPECT_EQ(text.back(), '\n') << name;
  }
}

// A file-size limit (ulimit -f): a write error naming the file instead of a kill by SIGXFSZ; the
// files keep whole lines and the trajectory evaluates.
TEST_F(RunReliabilityTest, FileSizeLimitIsANamedWriteErrorAndKeepsEarlierOutputs) {
  const std::string seq = Synth(40);
  const rlim_t limit = 2048;  // ~18 lines of timing.csv or trajectory.txt
  std::string output;
  const int status = RunToEnd(RunArgs(seq), &output, limit);
  EXPECT_EQ(status, 1) << output;
  EXPECT_NE(output.find("File too large"), std::string::npos) << output;
  EXPECT_TRUE(std::regex_search(output, std::regex(R"(cannot write \S+/(timing\.csv|trajectory\.txt))"))) << output;
  for (const std::string name : {"trajectory.txt", "keyframes.txt", "timing.csv"}) {
    const std::string path = out_ + "/" + name;
    ASSERT_TRUE(fs::exists(path)) << name;
    EXPECT_LE(fs::file_size(path), limit) << name;
    std::ifstream in(path, std::ios::binary);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ASSERT_FALSE(text.empty()) << name;
    EXPECT_EQ(text.back(), '\n') << name << " ends inside a line";
  }
  EXPECT_GE(PoseLines(out_ + "/trajectory.txt"), 5);
  Eval(seq);
}

// A corrupt PNG in the middle is skipped with a warning naming it, like a missing one, and counted.
TEST_F(RunReliabilityTest, CorruptFrameIsSkippedAndCounted) {
  const std::string seq = Synth(20);
  const std::string corrupt = Listed(seq, "rgb.txt")[12];
  std::ofstream(corrupt, std::ios::trunc) << "not a png";
  std::string output;
  EXPECT_EQ(RunToEnd(RunArgs(seq), &output), 0) << output;
  EXPECT_NE(output.find(corrupt), std::string::npos) << output;
  EXPECT_EQ(SummaryValue(output, R"(frames_skipped (\d+))"), 1) << output;
  EXPECT_EQ(SummaryValue(output, R"(\(processed (\d+)\))"), 19) << output;
  Eval(seq);
}

// Sequence.maxConsecutiveBadFrames bad frames in a row end the run with an error; what was
// tracked before is written.
TEST_F(RunReliabilityTest, ConsecutiveBadFramesFailTheRunAfterTheLimit) {
  const std::string seq = Synth(20);
  std::ofstream(seq + "/settings.yaml", std::ios::app) << "\nSequence.maxConsecutiveBadFrames: 3\n";
  const std::vector<std::string> depth = Listed(seq, "depth.txt");
  for (int i = 12; i < 15; ++i) std::ofstream(depth[i], std::ios::trunc) << "garbage";
  std::string output;
  EXPECT_EQ(RunToEnd(RunArgs(seq), &output), 1) << output;
  EXPECT_NE(output.find("3 frames in a row cannot be read"), std::string::npos) << output;
  EXPECT_NE(output.find(depth[14]), std::string::npos) << output;
  EXPECT_GE(PoseLines(out_ + "/trajectory.txt"), 8);
}

// All-zero depth: no pose at all, and the run says why (and fails).
TEST_F(RunReliabilityTest, AllZeroDepthSaysWhyNothingInitialised) {
  const std::string seq = Synth(8);
  for (const std::string& path : Listed(seq, "depth.txt"))
    ASSERT_TRUE(cv::imwrite(path, cv::Mat::zeros(cv::imread(path, cv::IMREAD_UNCHANGED).size(), CV_16UC1)));
  std::string output;
  EXPECT_EQ(RunToEnd(RunArgs(seq), &output), 1) << output;
  EXPECT_NE(output.find("never initialised: no valid depth"), std::string::npos) << output;
  EXPECT_EQ(PoseLines(out_ + "/trajectory.txt"), 0);
}

// Images of another size than Camera.width/height: an error naming the image and the keys.
TEST_F(RunReliabilityTest, ImageSizeOtherThanTheSettingsIsNamed) {
  const std::string seq = Synth(5);
  std::ifstream in(seq + "/settings.yaml");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  text = std::regex_replace(text, std::regex(R"(Camera\.width: *\d+)"), "Camera.width: 1280");
  text = std::regex_replace(text, std::regex(R"(Camera\.height: *\d+)"), "Camera.height: 960");
  const std::string settings = dir_ + "/big.yaml";
  std::ofstream(settings) << text;
  std::string output;
  EXPECT_NE(RunToEnd(RunArgs(seq, settings), &output), 0) << output;
  EXPECT_NE(output.find(Listed(seq, "rgb.txt")[0]), std::string::npos) << output;
  EXPECT_NE(output.find("Camera.width/Camera.height are 1280x960"), std::string::npos) << output;
}

}  // namespace
}  // namespace esdslam
