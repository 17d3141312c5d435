// The live viewer in a real browser (label slow): a short synthetic run with --viewer (any free
// port) and --viewer-keep (25 frames: the last ones still have keypoints removed as dynamic),
// the page loaded by headless Chromium (Debian's `chromium`,
// tools/install_deps.sh; WebGL through its software renderer SwiftShader) while the run's
// process serves it. The page loads (its title names the frame it drew), the 3-D canvas is not
// blank, and the numbers shown are the run's: frames = timing.csv rows, poses = trajectory.txt
// lines, keyframes = keyframes.txt lines. Then `esdslam view` of the same folder shows the same.
// ESDSLAM_VIEWER_SCREENSHOT=FILE copies the live screenshot there (docs/viewer.png).
#include <signal.h>
#include <sys/types.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "report/markup.h"
#include "support/program.h"
#include "support/temp_path.h"
#include "support/test_paths.h"

namespace esdslam {
namespace {

namespace fs = std::filesystem;

// A program started in the background whose output (stdout and stderr) is read line by line
// (blocking reads, no polling) until a line with `marker`; it serves until Stop (SIGTERM).
class Server {
 public:
  Server(const std::string& command, const std::string& marker) {
    pipe_ = ::popen(("cd '" + testing::SourceDir() + "' && echo $$ && exec " + command + " 2>&1").c_str(), "r");
    if (pipe_ == nullptr) return;
    char line[4096];
    if (std::fgets(line, sizeof(line), pipe_) != nullptr) pid_ = std::atoi(line);
    while (std::fgets(line, sizeof(line), pipe_) != nullptr) {
      output_ += line;
      if (output_.find(marker) != std::string::npos) {
        ready_ = true;
        break;
      }
    }
  }
  ~Server() { Stop(); }
  // Status of the program (-1: it did not exit normally).
  int Stop() {
    if (pipe_ == nullptr) return -1;
    if (pid_ > 0) ::kill(pid_, SIGTERM);
    char line[4096];
    while (std::fgets(line, sizeof(line), pipe_) != nullptr) output_ += line;
    const int status = ::pclose(pipe_);
    pipe_ = nullptr;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  bool ready() const { return ready_; }
  const std::string& output() const { return output_; }
  // The port from the line "... http://127.0.0.1:PORT/ ..."; 0 if none.
  int Port() const {
    const std::string key = "http://127.0.0.1:";
    const std::size_t at = output_.find(key);
    return at == std::string::npos ? 0 : std::atoi(output_.c_str() + at + key.size());
  }

 private:
  FILE* pipe_ = nullptr;
  int pid_ = 0;
  bool ready_ = false;
  std::string output_;
};

// Headless Chromium on `url` (?once=1: the snapshot, no event stream, so that the page settles):
// a screenshot into shot and the DOM after the scripts ran, returned.
std::string LoadPage(const std::string& dir, const std::string& url, const std::string& shot) {
  const std::string chromium = "timeout 180 chromium --headless --no-sandbox --no-first-run --hide-scrollbars "
                               "--use-angle=swiftshader --enable-unsafe-swiftshader --window-size=1280,800 "
                               "--virtual-time-budget=10000 --user-data-dir=" + dir + "/profile ";
  testing::ShellResult r = testing::RunShellInSourceDir(chromium + "--screenshot=" + shot + " '" + url + "'");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  r = testing::RunShellInSourceDir(chromium + "--dump-dom '" + url + "' 2>/dev/null > " + dir + "/dom.html");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  return testing::ReadTextFile(dir + "/dom.html");
}

// Share of the 3-D view's pixels (left of the 360 px side panel) that differ from its background.
double SceneInk(const std::string& shot_path) {
  const cv::Mat shot = cv::imread(shot_path, cv::IMREAD_COLOR);
  if (shot.empty() || shot.cols <= 360) return 0;
  const cv::Mat scene = shot(cv::Rect(0, 0, shot.cols - 360, shot.rows));
  cv::Mat diff;
  cv::absdiff(scene, cv::Scalar(0x1d, 0x18, 0x15), diff);  // #15181d as BGR
  cv::Mat grey;
  cv::transform(diff, grey, cv::Matx13f(1, 1, 1));
  return static_cast<double>(cv::countNonZero(grey > 30)) / static_cast<double>(grey.total());
}

void ExpectRunNumbers(const std::string& dom, const std::string& run) {
  const std::size_t frames = testing::DataLines(run + "/timing.csv") - 1;  // minus the header
  EXPECT_NE(dom.find("<title>ESD-SLAM viewer: frame " + std::to_string(frames) + "</title>"), std::string::npos)
      << dom.substr(0, 400);
  EXPECT_EQ(::esdslam::testing::MetricText(dom, "frames"), std::to_string(frames));
  EXPECT_EQ(::esdslam::testing::MetricText(dom, "poses"), std::to_string(testing::DataLines(run + "/trajectory.txt")));
  EXPECT_EQ(::esdslam::testing::MetricText(dom, "keyframes"), std::to_string(testing::DataLines(run + "/keyframes.txt")));
  EXPECT_NE(::esdslam::testing::MetricText(dom, "track_ms"), "");  // the stage panel
}

TEST(ViewerBrowser, LiveViewerOfASyntheticRunShowsTheRunsNumbers) {
  const std::string bin = testing::EsdslamProgram();
  ASSERT_TRUE(fs::exists(bin)) << "build the esdslam target first";
  ASSERT_EQ(testing::RunShellInSourceDir("command -v chromium").exit_code, 0) << "chromium is not installed (tools/install_deps.sh)";
  ASSERT_TRUE(fs::exists(testing::SourceDir() + "/tools/web/node_modules/three/build/three.module.js"))
      << "three.js is not installed: npm ci --prefix tools/web (tools/install_deps.sh)";
  const std::string dir = ::esdslam::testing::TestTempPath("viewer_browser");
  fs::create_directories(dir);
  const std::string seq = dir + "/seq", run = dir + "/run";
  const testing::ShellResult synth = testing::RunShellInSourceDir(bin + " synth --preset dynamic --frames 60 --seed 3 --out " + seq);
  ASSERT_EQ(synth.exit_code, 0) << synth.output;

  {
    // 20 frames: from frame 24 of this sequence the network labels 87 % of the image as a person
    // (a false blob on the synthetic pictures) and tracking is lost for four frames; the state
    // shown at the end would then be LOST.
    Server live(bin + " run --settings " + seq + "/settings.yaml --sequence " + seq + " --out " + run +
                    " --single-thread --dense --max-frames 20 --viewer 0 --viewer-keep",
                "until Ctrl-C");
    ASSERT_TRUE(live.ready()) << live.output();
    ASSERT_GT(live.Port(), 0) << live.output();
    const std::string url = "http://127.0.0.1:" + std::to_string(live.Port()) + "/?once=1";
    const std::string dom = LoadPage(dir, url, dir + "/live.png");
    ExpectRunNumbers(dom, run);
    EXPECT_EQ(::esdslam::testing::MetricText(dom, "state"), "OK");
    EXPECT_GT(SceneInk(dir + "/live.png"), 0.02) << "the 3-D view is (nearly) blank";
    EXPECT_EQ(live.Stop(), 0) << live.output();  // SIGTERM while serving the finished run: status 0
  }
  if (const char* copy = std::getenv("ESDSLAM_VIEWER_SCREENSHOT"))
    fs::copy_file(dir + "/live.png", copy, fs::copy_options::overwrite_existing);

  Server replay(bin + " view " + run + " --port 0", "http://127.0.0.1:");
  ASSERT_TRUE(replay.ready()) << replay.output();
  const std::string dom = LoadPage(dir, "http://127.0.0.1:" + std::to_string(replay.Port()) + "/?once=1",
                                   dir + "/replay.png");
  ExpectRunNumbers(dom, run);
  EXPECT_GT(SceneInk(dir + "/replay.png"), 0.02) << "the replayed 3-D view is (nearly) blank";
  EXPECT_EQ(replay.Stop(), 0) << replay.output();
}

}  // namespace
}  // namespace esdslam
