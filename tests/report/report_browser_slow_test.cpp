// The run report in a real browser (label slow): a short synthetic run with --report, the page
// rendered by headless Chromium (Debian's `chromium`, tools/install_deps.sh). The screenshot is
// not blank, and the numbers in the rendered page (Chromium's --dump-dom, i.e. after parsing)
// are the run's: the ATE/RPE that `esdslam eval` prints for its trajectory, its frame, pose and
// keyframe counts, and the crowded frames counted from its timing.csv.
// ESDSLAM_REPORT_SCREENSHOT=FILE copies the screenshot there (docs/report_screenshot.png).
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "report/markup.h"
#include "report/run_files.h"
#include "support/program.h"
#include "support/temp_path.h"
#include "support/test_paths.h"

namespace esdslam {
namespace {

namespace fs = std::filesystem;

TEST(ReportBrowser, ReportOfASyntheticRunRendersWithTheRunsNumbers) {
  const std::string bin = testing::EsdslamProgram();
  ASSERT_TRUE(fs::exists(bin)) << "build the esdslam target first";
  ASSERT_EQ(testing::RunShellInSourceDir("command -v chromium").exit_code, 0) << "chromium is not installed (tools/install_deps.sh)";
  const std::string dir = ::esdslam::testing::TestTempPath("report_browser");
  fs::create_directories(dir);
  const std::string seq = dir + "/seq", run = dir + "/run";

  testing::ShellResult r = testing::RunShellInSourceDir(bin + " synth --preset dynamic --frames 60 --seed 3 --out " + seq);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = testing::RunShellInSourceDir(bin + " run --settings " + seq + "/settings.yaml --sequence " + seq + " --out " + run +
            " --single-thread --debug-frames " + run + "/debug --report");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ASSERT_TRUE(fs::exists(run + "/report.html")) << r.output;
  const testing::ShellResult eval = testing::RunShellInSourceDir(bin + " eval " + seq + "/groundtruth.txt " + run + "/trajectory.txt");
  ASSERT_EQ(eval.exit_code, 0) << eval.output;

  // Chromium: its own profile folder, no network use by the page (it has no external reference).
  const std::string chromium = "timeout 180 chromium --headless --no-sandbox --disable-gpu --no-first-run "
                               "--user-data-dir=" + dir + "/profile --hide-scrollbars ";
  const std::string url = "file://" + run + "/report.html";
  r = testing::RunShellInSourceDir(chromium + "--window-size=1100,2400 --screenshot=" + dir + "/shot.png " + url);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = testing::RunShellInSourceDir(chromium + "--dump-dom " + url + " > " + dir + "/dom.html");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string dom = testing::ReadTextFile(dir + "/dom.html");

  // The numbers shown are the run's.
  std::istringstream lines(eval.output);
  std::string name, value;
  int metrics = 0;
  while (lines >> name >> value) {
    if (name.rfind("ate_", 0) != 0 && name.rfind("rpe_", 0) != 0 && name != "pairs") continue;
    EXPECT_EQ(::esdslam::testing::MetricText(dom, name), value) << name;
    ++metrics;
  }
  EXPECT_GE(metrics, 7);
  EXPECT_EQ(::esdslam::testing::MetricText(dom, "frames"), "60");
  EXPECT_EQ(::esdslam::testing::MetricText(dom, "poses"), std::to_string(testing::DataLines(run + "/trajectory.txt")));
  EXPECT_EQ(::esdslam::testing::MetricText(dom, "keyframes"), std::to_string(testing::DataLines(run + "/keyframes.txt")));
  const TimingTable timing = ReadTimingCsv(run + "/timing.csv");
  std::size_t crowded = 0;
  for (double f : timing.Numbers("dynamic_fraction")) crowded += f > 0.5;
  EXPECT_EQ(::esdslam::testing::MetricText(dom, "crowded_frames"), std::to_string(crowded));
  EXPECT_EQ(::esdslam::testing::CountOf(dom, "<svg"), 7u);
  const std::size_t pictures = ::esdslam::testing::CountOf(dom, "src=\"data:image/png;base64,");
  EXPECT_TRUE(pictures == 3 || pictures == 4) << pictures;  // 3 evenly spaced + the most crowded (may coincide)

  // The page rendered: the screenshot is not blank (a white page would have no spread).
  const cv::Mat shot = cv::imread(dir + "/shot.png", cv::IMREAD_COLOR);
  ASSERT_FALSE(shot.empty()) << r.output;
  EXPECT_EQ(shot.cols, 1100);
  cv::Mat grey;
  cv::cvtColor(shot, grey, cv::COLOR_BGR2GRAY);
  const double ink = static_cast<double>(cv::countNonZero(grey < 200)) / static_cast<double>(grey.total());
  EXPECT_GT(ink, 0.01) << "screenshot is (nearly) blank";
  cv::Scalar mean, stddev;
  cv::meanStdDev(shot, mean, stddev);
  EXPECT_GT(stddev[0] + stddev[1] + stddev[2], 20.0);
  if (const char* copy = std::getenv("ESDSLAM_REPORT_SCREENSHOT")) fs::copy_file(dir + "/shot.png", copy, fs::copy_options::overwrite_existing);
}

}  // namespace
}  // namespace esdslam
