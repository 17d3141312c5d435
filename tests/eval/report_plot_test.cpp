#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "common/error.h"
#include "eval/plot.h"
#include "eval/report.h"
#include "io/test_files.h"

namespace esdslam {
namespace {

// 3 s at 10 Hz on a circle; the estimate is the ground truth shifted by 0.1 m in x for the
// second half (ATE after alignment is then non-zero but small).
void MakeTrajectories(std::vector<StampedPose>& groundtruth, std::vector<StampedPose>& estimate) {
  for (int i = 0; i < 30; ++i) {
    const double t = 0.1 * i;
    const Vec3 position(std::cos(t), std::sin(t), 0.1 * t);
    groundtruth.push_back({t, Rigid3(Quat::Identity(), position)});
    estimate.push_back({t + 0.001, Rigid3(Quat::Identity(), position + Vec3(i >= 15 ? 0.1 : 0.0, 0, 0))});
  }
}

TEST(Report, TextAndJsonListTheMetricsInOrder) {
  std::vector<StampedPose> groundtruth, estimate;
  MakeTrajectories(groundtruth, estimate);
  const EvalReport report = Evaluate(groundtruth, estimate);
  ASSERT_TRUE(report.rpe_per_frame.has_value());
  ASSERT_TRUE(report.rpe_per_second.has_value());
  EXPECT_EQ(report.rpe_per_frame->pairs, 29u);
  EXPECT_EQ(report.rpe_per_second->pairs, 20u);  // i + 10 frames <= 29
  // Per frame only the (14, 15) step carries the 0.1 m jump.
  EXPECT_NEAR(report.rpe_per_frame->translation_m.max, 0.1, 1e-9);
  const std::string text = FormatReportText(report);
  std::istringstream lines(text);
  std::vector<std::string> names;
  std::string name, value;
  while (lines >> name >> value) names.push_back(name);
  const std::vector<std::string> head = {"ate_rmse", "ate_mean", "ate_median", "ate_std", "ate_min", "ate_max", "pairs"};
  ASSERT_GE(names.size(), head.size());
  EXPECT_EQ(std::vector<std::string>(names.begin(), names.begin() + 7), head);
  EXPECT_NE(text.find("\npairs 30\n"), std::string::npos);
  EXPECT_NE(text.find("rpe_frame_trans_rmse "), std::string::npos);
  EXPECT_NE(text.find("rpe_second_rot_rmse_deg "), std::string::npos);
  const std::string json = FormatReportJson(report);
  EXPECT_EQ(json.front(), '{');
  EXPECT_NE(json.find("\"ate_rmse\": "), std::string::npos);
  EXPECT_NE(json.find("\"pairs\": 30"), std::string::npos);
}

TEST(Report, ShortTrajectoryHasNoPerSecondRpe) {
  std::vector<StampedPose> groundtruth, estimate;
  MakeTrajectories(groundtruth, estimate);
  groundtruth.resize(8);  // 0.7 s
  estimate.resize(8);
  const EvalReport report = Evaluate(groundtruth, estimate);
  EXPECT_TRUE(report.rpe_per_frame.has_value());
  EXPECT_FALSE(report.rpe_per_second.has_value());
  EXPECT_EQ(FormatReportText(report).find("rpe_second"), std::string::npos);
}

TEST(Plot, WritesSvgAndPng) {
  testing::TempDir dir;
  std::vector<Vec3> groundtruth, estimate;
  for (int i = 0; i < 100; ++i) {
    groundtruth.emplace_back(std::cos(0.05 * i), std::sin(0.05 * i), 0);
    estimate.emplace_back(1.02 * std::cos(0.05 * i), std::sin(0.05 * i), 0);
  }
  PlotTrajectoriesXY(groundtruth, estimate, dir.Path("plot.svg"));
  std::ifstream in(dir.Path("plot.svg"));
  const std::string svg((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(svg.rfind("<svg", 0), 0u);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
  EXPECT_NE(svg.find("ground truth"), std::string::npos);
  std::size_t polylines = 0;
  for (std::size_t at = svg.find("<polyline"); at != std::string::npos; at = svg.find("<polyline", at + 1)) ++polylines;
  EXPECT_EQ(polylines, 2u);
  PlotTrajectoriesXY(groundtruth, estimate, dir.Path("sub/plot.PNG"));
  const cv::Mat png = cv::imread(dir.Path("sub/plot.PNG"));
  ASSERT_FALSE(png.empty());
  EXPECT_EQ(png.size(), cv::Size(800, 800));
  // Something other than white was drawn in the plot area.
  cv::Mat grey;
  cv::extractChannel(png, grey, 0);
  EXPECT_GT(cv::countNonZero(grey < 128), 500);
  EXPECT_THROW(PlotTrajectoriesXY(groundtruth, estimate, dir.Path("plot.pdf")), Error);
  EXPECT_THROW(PlotTrajectoriesXY({}, {}, dir.Path("p.svg")), Error);
}

}  // namespace
}  // namespace esdslam
