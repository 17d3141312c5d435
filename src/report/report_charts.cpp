// The chart sections of the run report: trajectory, error over time, stage times and dynamic
// fraction (report/report_sections.h).
#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "eval/plot.h"
#include "report/html.h"
#include "report/report_sections.h"
#include "report/svg_chart.h"
#include "system/frame_columns.h"

namespace esdslam {
namespace {

const char* const kPalette[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd",
                                "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf"};

// The estimate's positions, aligned to the ground truth when there is an evaluation.
std::vector<Vec3> EstimatePositions(const ReportData& data) {
  std::vector<Vec3> points;
  for (const StampedPose& pose : data.files->trajectory) {
    const Vec3 p = pose.world_from_cam.translation();
    points.push_back(data.eval ? data.eval->ate.groundtruth_from_estimate * p : p);
  }
  return points;
}

std::string Figure(const std::string& svg, const std::string& caption, const std::string& css_class = "") {
  return (css_class.empty() ? "<figure>" : "<figure class=\"" + css_class + "\">") + svg + "<figcaption>" + EscapeHtml(caption) + "</figcaption></figure>\n";
}

// Shading of the crowded frames on a chart, with its legend text.
void Shade(const ReportData& data, const ReportOptions& options, ChartOptions& chart) {
  chart.shaded_x = data.crowded;
  chart.shaded_label = fmt::format("dynamic fraction > {:g}", options.crowded_fraction);
}

}  // namespace

std::string TrajectorySection(const ReportData& data) {
  const std::vector<Vec3> estimate = EstimatePositions(data);
  std::vector<Vec3> truth;
  if (data.groundtruth)
    for (const StampedPose& pose : *data.groundtruth) truth.push_back(pose.world_from_cam.translation());
  std::string html = "<section id=\"trajectory\"><h2>Trajectory</h2>\n";
  if (!data.eval) html += "<p class=\"note\">No ground truth given: the estimate alone, unaligned.</p>\n";
  if (estimate.empty() && truth.empty()) return html + "<p class=\"note\">The run has no poses.</p></section>\n";
  html += Figure(TrajectoriesXYSvg(truth, estimate),
                 data.eval ? "Top view (x-y, metres): ground truth black, estimate blue after rigid alignment."
                           : "Top view (x-y, metres) of the estimate.",
                 "topview");
  const char* const axis_names[] = {"x", "y", "z"};
  for (int axis = 0; axis < 3; ++axis) {
    ChartSeries est{"estimate", "#1f77b4", {}, {}};
    for (std::size_t i = 0; i < estimate.size(); ++i) {
      est.x.push_back(data.files->trajectory[i].timestamp - data.t0);
      est.y.push_back(estimate[i][axis]);
    }
    std::vector<ChartSeries> series;
    if (data.groundtruth) {
      ChartSeries gt{"ground truth", "black", {}, {}};
      for (std::size_t i = 0; i < truth.size(); ++i) {
        gt.x.push_back((*data.groundtruth)[i].timestamp - data.t0);
        gt.y.push_back(truth[i][axis]);
      }
      series.push_back(std::move(gt));
    }
    series.push_back(std::move(est));
    ChartOptions chart;
    chart.title = fmt::format("{} over time", axis_names[axis]);
    chart.y_label = fmt::format("{} [m]", axis_names[axis]);
    chart.height_px = 200;
    chart.y_from_zero = false;
    html += Figure(LineChartSvg(series, chart), "");
  }
  return html + "</section>\n";
}

std::string ErrorSection(const ReportData& data, const ReportOptions& options) {
  std::string html = "<section id=\"error\"><h2>Error over time</h2>\n";
  if (!data.eval) return html + "<p class=\"note\">No ground truth given: no error.</p></section>\n";
  ChartSeries error{"ATE translation error", "#d62728", {}, {}};
  for (const AtePair& pair : data.eval->ate.pairs) {
    error.x.push_back(data.files->trajectory[pair.estimate_index].timestamp - data.t0);
    error.y.push_back(pair.error_m);
  }
  ChartOptions chart;
  chart.title = "Absolute trajectory error per pose";
  chart.y_label = "error [m]";
  Shade(data, options, chart);
  html += Figure(LineChartSvg({error}, chart),
                 fmt::format("|p_gt - S p_est| after alignment, {} poses; shaded: the {} frames where the dynamic "
                             "mask covers more than {:g} of the image.",
                             data.eval->ate.pairs.size(), data.crowded_frames, options.crowded_fraction));
  return html + "</section>\n";
}

std::string TimingSection(const ReportData& data, const ReportOptions& options) {
  const TimingTable& timing = data.files->timing;
  std::string html = "<section id=\"timing\"><h2>Stage times and dynamic fraction</h2>\n";
  if (timing.rows.empty() || !timing.Has("timestamp"))
    return html + "<p class=\"note\">timing.csv has no frames.</p></section>\n";
  std::vector<double> time = timing.Numbers("timestamp");
  for (double& t : time) t -= data.t0;
  std::vector<ChartSeries> stages;
  for (const FrameColumn& column : FrameColumns()) {
    if (column.summary == nullptr || !column.csv || std::string(column.unit) != "ms" || !timing.Has(column.name))
      continue;
    std::vector<double> values = timing.Numbers(column.name);
    if (std::all_of(values.begin(), values.end(), [](double v) { return v == 0 || std::isnan(v); }))
      continue;  // the stage did not run
    stages.push_back({column.summary, kPalette[stages.size() % 10], time, std::move(values)});
  }
  ChartOptions chart;
  chart.title = "Per-stage time per frame";
  chart.y_label = "time [ms]";
  Shade(data, options, chart);
  if (stages.empty()) {
    html += "<p class=\"note\">No stage times in timing.csv.</p>\n";
  } else {
    html += Figure(LineChartSvg(stages, chart), "Wall-clock milliseconds of each stage that ran (timing.csv).");
  }
  if (!timing.Has("dynamic_fraction")) return html + "<p class=\"note\">No dynamic_fraction column.</p></section>\n";
  ChartSeries fraction{"dynamic_fraction", "#9467bd", time, timing.Numbers("dynamic_fraction")};
  ChartSeries threshold{"threshold", "#555", {time.front(), time.back()},
                        {options.crowded_fraction, options.crowded_fraction}, true};
  chart.title = "Dynamic fraction per frame";
  chart.y_label = "share of image";
  html += Figure(LineChartSvg({fraction, threshold}, chart), "Share of the image on the dynamic mask.");
  return html + "</section>\n";
}

}  // namespace esdslam
