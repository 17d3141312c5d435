// The run report from a run's files: the readers of the output folder, the crowded frames and
// sampled pictures, and the page: well formed, self-contained, and its numbers are the inputs'.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "common/error.h"
#include "eval/report.h"
#include "io/test_files.h"
#include "report/markup.h"
#include "report/report_sections.h"
#include "report/run_files.h"
#include "report/run_report.h"

namespace esdslam {
namespace {

using testing::CheckMarkup;
using testing::CountOf;
using testing::MetricText;

constexpr int kFrames = 40;

double Time(int i) { return 100.0 + 0.1 * i; }

// Frames 10..14 and 30 are crowded (dynamic fraction 0.6 and 0.9), the rest 0.1.
double Dynamic(int i) { return (i >= 10 && i < 15) ? 0.6 : (i == 30 ? 0.9 : 0.1); }

void WriteRun(const std::string& dir, std::vector<StampedPose>* groundtruth) {
  std::vector<StampedPose> estimate, keyframes;
  std::ofstream csv(dir + "/timing.csv");
  csv << "timestamp,track_ms,state,lost,dynamic_fraction,keypoints,dynamic_keypoints\n";
  for (int i = 0; i < kFrames; ++i) {
    const Vec3 p(std::cos(0.1 * i), std::sin(0.1 * i), 0.02 * i);
    groundtruth->push_back({Time(i), Rigid3(Quat::Identity(), p)});
    estimate.push_back({Time(i) + 0.001, Rigid3(Quat::Identity(), p + Vec3(0.01 * (i % 3), 0, 0))});
    if (i % 10 == 0) keyframes.push_back(estimate.back());
    csv << fmt::format("{:.6f},{:.3f},OK,0,{:.4f},{},{}\n", Time(i), 10.0 + i, Dynamic(i), 900 + i, i);
  }
  WriteTumTrajectory(dir + "/trajectory.txt", estimate);
  WriteTumTrajectory(dir + "/keyframes.txt", keyframes);
  std::ofstream(dir + "/settings_used.yaml") << "%YAML:1.0\nCamera.fx: 525\nSemantic.dynamicClasses: \"person\"\n";
}

TEST(RunFiles, ReadsTimingByNameAndNamesTheLineOfABadRow) {
  testing::TempDir dir;
  std::ofstream(dir.Path("timing.csv")) << "timestamp,state,track_ms\n1.5,OK,2.25\n1.6,LOST,x\n";
  const TimingTable table = ReadTimingCsv(dir.Path("timing.csv"));
  ASSERT_EQ(table.rows.size(), 2u);
  EXPECT_EQ(table.Text("state"), (std::vector<std::string>{"OK", "LOST"}));
  EXPECT_DOUBLE_EQ(table.Numbers("track_ms")[0], 2.25);
  EXPECT_TRUE(std::isnan(table.Numbers("track_ms")[1]));
  EXPECT_THROW(table.Numbers("nope"), Error);
  std::ofstream(dir.Path("bad.csv")) << "a,b\n1,2\n1,2,3\n";
  try {
    ReadTimingCsv(dir.Path("bad.csv"));
    FAIL() << "expected an error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 3);
  }
  EXPECT_THROW(ReadTimingCsv(dir.Path("missing.csv")), InputError);
}

TEST(RunFiles, ReadsFlatSettingsAndListsDebugPicturesByTime) {
  testing::TempDir dir;
  std::ofstream(dir.Path("s.yaml")) << "%YAML:1.0\n# c\nA.b: 1\nC: \"x: y\"\n";
  const auto settings = ReadFlatYaml(dir.Path("s.yaml"));
  ASSERT_EQ(settings.size(), 2u);
  EXPECT_EQ(settings[1].first, "C");
  EXPECT_EQ(settings[1].second, "\"x: y\"");
  std::ofstream(dir.Path("bad.yaml")) << "A: 1\nnovalue\n";
  EXPECT_THROW(ReadFlatYaml(dir.Path("bad.yaml")), InputError);
  const cv::Mat image(4, 4, CV_8UC3, cv::Scalar(0, 0, 0));
  cv::imwrite(dir.Path("2.500000.png"), image);
  cv::imwrite(dir.Path("1.250000.png"), image);
  cv::imwrite(dir.Path("notes.png"), image);
  std::ofstream(dir.Path("3.0.txt")) << "x";
  const std::vector<DebugPicture> pictures = ListDebugPictures(dir.Path());
  ASSERT_EQ(pictures.size(), 2u);
  EXPECT_DOUBLE_EQ(pictures[0].timestamp, 1.25);
  EXPECT_DOUBLE_EQ(pictures[1].timestamp, 2.5);
  EXPECT_TRUE(ListDebugPictures(dir.Path("absent")).empty());
}

TEST(RunReport, CrowdedFramesMergeIntoIntervals) {
  testing::TempDir dir;
  std::vector<StampedPose> groundtruth;
  WriteRun(dir.Path(), &groundtruth);
  const TimingTable timing = ReadTimingCsv(dir.Path("timing.csv"));
  std::size_t frames = 0;
  const auto intervals = CrowdedIntervals(timing, 0.5, Time(0), &frames);
  EXPECT_EQ(frames, 6u);
  ASSERT_EQ(intervals.size(), 2u);
  EXPECT_NEAR(intervals[0].first, 0.95, 1e-6);  // frame 10 at 1.0 s minus half a frame
  EXPECT_NEAR(intervals[0].second, 1.45, 1e-6);
  EXPECT_NEAR(intervals[1].first, 2.95, 1e-6);
  EXPECT_NEAR(intervals[1].second, 3.05, 1e-6);
  EXPECT_EQ(CrowdedIntervals(timing, 0.95, Time(0), &frames).size(), 0u);
  EXPECT_EQ(frames, 0u);
}

TEST(RunReport, SampledPicturesIncludeTheMostCrowdedFrame) {
  testing::TempDir dir;
  std::vector<StampedPose> groundtruth;
  WriteRun(dir.Path(), &groundtruth);
  const TimingTable timing = ReadTimingCsv(dir.Path("timing.csv"));
  std::vector<DebugPicture> pictures;
  for (int i = 0; i < kFrames; ++i) pictures.push_back({Time(i), ""});
  const std::vector<std::size_t> chosen = SampleDebugPictures(pictures, timing, 4);
  EXPECT_EQ(chosen, (std::vector<std::size_t>{0, 19, 30, 39}));  // 3 evenly spaced + frame 30
  EXPECT_EQ(SampleDebugPictures(pictures, timing, 1), std::vector<std::size_t>{30});
  EXPECT_TRUE(SampleDebugPictures(pictures, timing, 0).empty());
  EXPECT_TRUE(SampleDebugPictures({}, timing, 4).empty());
}

TEST(RunReport, PageIsWellFormedSelfContainedAndShowsTheInputsNumbers) {
  testing::TempDir dir;
  std::vector<StampedPose> groundtruth;
  WriteRun(dir.Path(), &groundtruth);
  WriteTumTrajectory(dir.Path("gt.txt"), groundtruth);
  ReportOptions options;
  options.out_dir = dir.Path();
  options.groundtruth_path = dir.Path("gt.txt");
  const std::string path = WriteRunReport(options);
  EXPECT_EQ(path, dir.Path("report.html"));
  std::ifstream in(path);
  const std::string html((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(CheckMarkup(html), "");
  // Self-contained: no script, no stylesheet link, no remote or file source.
  EXPECT_EQ(html.find("<script"), std::string::npos);
  EXPECT_EQ(html.find("<link"), std::string::npos);
  EXPECT_EQ(html.find("src=\"http"), std::string::npos);
  EXPECT_EQ(html.find("url("), std::string::npos);
  EXPECT_EQ(CountOf(html, "href=\""), CountOf(html, "href=\"#"));
  // The metrics are those `esdslam eval` prints, with the same digits.
  const EvalReport eval = Evaluate(ReadTumTrajectory(dir.Path("gt.txt")), ReadTumTrajectory(dir.Path("trajectory.txt")));
  for (const auto& [name, value] : ReportMetrics(eval)) EXPECT_EQ(MetricText(html, name), FormatMetricValue(name, value)) << name;
  EXPECT_EQ(MetricText(html, "frames"), std::to_string(kFrames));
  EXPECT_EQ(MetricText(html, "poses"), std::to_string(kFrames));
  EXPECT_EQ(MetricText(html, "keyframes"), "4");
  EXPECT_EQ(MetricText(html, "crowded_frames"), "6");
  EXPECT_EQ(MetricText(html, "mean_track_ms"), "29.5");  // 10..49
  EXPECT_EQ(MetricText(html, "median_keypoints"), "920");  // upper middle of 900..939
  // Shading: the error chart, the stage-time chart and the dynamic-fraction chart, 2 intervals each.
  EXPECT_EQ(CountOf(html, "class=\"shade\""), 6u);
  EXPECT_NE(html.find("<td>Camera.fx</td><td>525</td>"), std::string::npos);
  EXPECT_NE(html.find("id=\"no-debug-frames\""), std::string::npos);
  EXPECT_EQ(CountOf(html, "<svg"), 7u);  // top view, x, y, z, error, stage times, dynamic fraction
}

TEST(RunReport, EmbedsSampledDebugPicturesScaled) {
  testing::TempDir dir;
  std::vector<StampedPose> groundtruth;
  WriteRun(dir.Path(), &groundtruth);
  std::filesystem::create_directories(dir.Path("debug"));
  for (int i = 0; i < kFrames; i += 5)
    cv::imwrite(dir.Path(fmt::format("debug/{:.6f}.png", Time(i))), cv::Mat(240, 640, CV_8UC3, cv::Scalar(0, 128, 0)));
  ReportOptions options;
  options.out_dir = dir.Path();
  options.debug_frames_dir = dir.Path("debug");
  options.max_debug_frames = 3;
  const RunFiles files = ReadRunFiles(options.out_dir, options.debug_frames_dir);
  ASSERT_EQ(files.debug_pictures.size(), 8u);
  const std::string html = BuildRunReportHtml(files, nullptr, options);
  EXPECT_EQ(CheckMarkup(html), "");
  EXPECT_EQ(CountOf(html, "src=\"data:image/png;base64,iVBORw0KGgo"), 3u);  // the PNG signature
  EXPECT_NE(html.find("dynamic fraction 0.9000"), std::string::npos);      // frame 30 is one of them
  EXPECT_EQ(html.find("id=\"no-debug-frames\""), std::string::npos);
  EXPECT_EQ(MetricText(html, "ate_rmse"), "");  // no ground truth: no accuracy
  EXPECT_NE(html.find("No ground truth given"), std::string::npos);
}

TEST(RunReport, OptionsAreChecked) {
  ReportOptions options;
  EXPECT_THROW(options.Check(), Error);  // no folder
  options.out_dir = "x";
  options.Check();
  options.crowded_fraction = 0;
  EXPECT_THROW(options.Check(), Error);
  options.crowded_fraction = 0.5;
  options.max_debug_frames = 51;
  EXPECT_THROW(options.Check(), Error);
  options.max_debug_frames = 4;
  options.debug_frame_width_px = 10;
  EXPECT_THROW(options.Check(), Error);
}

TEST(RunReport, MissingRunFilesNameTheFile) {
  testing::TempDir dir;
  ReportOptions options;
  options.out_dir = dir.Path();
  try {
    WriteRunReport(options);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("trajectory.txt"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace esdslam
