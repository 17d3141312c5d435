// The picture and table sections of the run report, and the choice of crowded frames and
// sampled pictures (report/report_sections.h).
#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "common/error.h"
#include "report/html.h"
#include "report/report_sections.h"
#include "system/frame_columns.h"
#include "system/frame_log.h"

namespace esdslam {
namespace {

double MedianSpacing(const std::vector<double>& times) {
  std::vector<double> gaps;
  for (std::size_t i = 1; i < times.size(); ++i) gaps.push_back(times[i] - times[i - 1]);
  if (gaps.empty()) return 0;
  std::nth_element(gaps.begin(), gaps.begin() + gaps.size() / 2, gaps.end());
  return gaps[gaps.size() / 2];
}

// The timing.csv row of a timestamp (the debug picture's name has 6 decimals, as the CSV).
int RowAt(const std::vector<double>& times, double timestamp) {
  for (std::size_t i = 0; i < times.size(); ++i)
    if (std::abs(times[i] - timestamp) < 5e-6) return static_cast<int>(i);
  return -1;
}

std::string Cell(const TimingTable& timing, int row, const std::string& column) {
  if (row < 0 || !timing.Has(column)) return "?";
  return timing.Text(column)[static_cast<std::size_t>(row)];
}

std::vector<std::uint8_t> ScaledPng(const std::string& path, int width_px) {
  const cv::Mat image = cv::imread(path, cv::IMREAD_COLOR);
  if (image.empty()) throw Error("cannot read debug picture " + path);
  cv::Mat scaled = image;
  if (image.cols > width_px) {
    const int height = std::max(1, static_cast<int>(std::lround(double(image.rows) * width_px / image.cols)));
    cv::resize(image, scaled, cv::Size(width_px, height), 0, 0, cv::INTER_AREA);
  }
  std::vector<std::uint8_t> png;
  if (!cv::imencode(".png", scaled, png)) throw Error("cannot encode debug picture " + path);
  return png;
}

std::string UnitOf(const std::string& column) {
  for (const FrameColumn& c : FrameColumns())
    if (column == c.name) return c.unit;
  return "";
}

}  // namespace

std::vector<std::pair<double, double>> CrowdedIntervals(const TimingTable& timing, double fraction, double t0,
                                                        std::size_t* frames) {
  std::vector<std::pair<double, double>> intervals;
  if (frames != nullptr) *frames = 0;
  if (!timing.Has("dynamic_fraction") || !timing.Has("timestamp")) return intervals;
  const std::vector<double> times = timing.Numbers("timestamp"), dynamic = timing.Numbers("dynamic_fraction");
  const double half = 0.5 * MedianSpacing(times);
  for (std::size_t i = 0; i < times.size(); ++i) {
    if (!(dynamic[i] > fraction)) continue;
    if (frames != nullptr) ++*frames;
    const double begin = times[i] - t0 - half, end = times[i] - t0 + half;
    if (!intervals.empty() && begin <= intervals.back().second + 1e-9) {
      intervals.back().second = end;
    } else {
      intervals.emplace_back(begin, end);
    }
  }
  return intervals;
}

std::vector<std::size_t> SampleDebugPictures(const std::vector<DebugPicture>& pictures, const TimingTable& timing,
                                             int count) {
  std::vector<std::size_t> chosen;
  const std::size_t n = pictures.size();
  if (n == 0 || count <= 0) return chosen;
  std::size_t crowded = 0;  // the picture with the largest dynamic fraction
  if (timing.Has("dynamic_fraction") && timing.Has("timestamp")) {
    const std::vector<double> times = timing.Numbers("timestamp"), dynamic = timing.Numbers("dynamic_fraction");
    double best = -1;
    for (std::size_t i = 0; i < n; ++i) {
      const int row = RowAt(times, pictures[i].timestamp);
      if (row >= 0 && dynamic[static_cast<std::size_t>(row)] > best) best = dynamic[static_cast<std::size_t>(row)], crowded = i;
    }
  }
  chosen.push_back(crowded);
  const std::size_t evenly = std::min<std::size_t>(n, static_cast<std::size_t>(count)) - 1;
  for (std::size_t k = 0; k < evenly; ++k) chosen.push_back(evenly == 1 ? 0 : k * (n - 1) / (evenly - 1));
  std::sort(chosen.begin(), chosen.end());
  chosen.erase(std::unique(chosen.begin(), chosen.end()), chosen.end());
  return chosen;
}

std::string DebugSection(const ReportData& data, const ReportOptions& options) {
  const RunFiles& files = *data.files;
  std::string html = "<section id=\"debug\"><h2>Debug frames</h2>\n";
  if (files.debug_pictures.empty())
    return html + "<p class=\"note\" id=\"no-debug-frames\">The run wrote no debug pictures (run with "
                  "<code>--debug-frames DIR</code> and give the report the same folder).</p></section>\n";
  html += "<p>Kept keypoints green, removed by the semantic mask red, removed by the geometry check magenta; "
          "the refined semantic mask tinted cyan, the geometry mask magenta.</p>\n<div class=\"frames\">\n";
  const std::vector<double> times =
      files.timing.Has("timestamp") ? files.timing.Numbers("timestamp") : std::vector<double>();
  for (std::size_t index : SampleDebugPictures(files.debug_pictures, files.timing, options.max_debug_frames)) {
    const DebugPicture& picture = files.debug_pictures[index];
    const int row = RowAt(times, picture.timestamp);
    const std::string caption =
        fmt::format("t = {:.3f} s (frame {}), dynamic fraction {}, keypoints {} ({} dynamic)", picture.timestamp - data.t0,
                    row, Cell(files.timing, row, "dynamic_fraction"), Cell(files.timing, row, "keypoints"),
                    Cell(files.timing, row, "dynamic_keypoints"));
    html += "<figure class=\"debug-frame\">" +
            PngImageTag(ScaledPng(picture.path, options.debug_frame_width_px), caption, options.debug_frame_width_px) +
            "<figcaption>" + EscapeHtml(caption) + "</figcaption></figure>\n";
  }
  return html + "</div></section>\n";
}

std::string SummarySection(const ReportData& data, const ReportOptions& options) {
  const RunFiles& files = *data.files;
  std::vector<std::vector<HtmlCell>> rows = {
      {{"frames"}, {std::to_string(files.timing.rows.size()), "frames"}, {"rows of timing.csv"}},
      {{"poses"}, {std::to_string(files.trajectory.size()), "poses"}, {"lines of trajectory.txt"}},
      {{"keyframes"}, {std::to_string(files.keyframes.size()), "keyframes"}, {"lines of keyframes.txt"}},
      {{"crowded frames"}, {std::to_string(data.crowded_frames), "crowded_frames"},
       {fmt::format("dynamic_fraction > {:g}", options.crowded_fraction)}}};
  if (data.eval) {
    for (const auto& [name, value] : ReportMetrics(*data.eval))
      rows.push_back({{name}, {FormatMetricValue(name, value), name}, {"esdslam eval"}});
  }
  std::string html = "<section id=\"summary\"><h2>Summary</h2>\n" + HtmlTable({"quantity", "value", "source"}, rows);
  std::vector<std::vector<HtmlCell>> stats;
  for (const std::string& column : files.timing.columns) {
    std::vector<double> values = files.timing.Numbers(column);
    values.erase(std::remove_if(values.begin(), values.end(), [](double v) { return std::isnan(v); }), values.end());
    if (column == "timestamp" || values.empty()) continue;
    const MeanMedian mm = ComputeMeanMedian(values);
    const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
    stats.push_back({{column}, {UnitOf(column)}, {fmt::format("{:.4g}", mm.mean), "mean_" + column},
                     {fmt::format("{:.4g}", mm.median), "median_" + column}, {fmt::format("{:.4g}", *lo)},
                     {fmt::format("{:.4g}", *hi)}});
  }
  html += "<h3>Per-frame columns (timing.csv)</h3>\n" + HtmlTable({"column", "unit", "mean", "median", "min", "max"}, stats);
  if (!options.run_summary.empty())
    html += "<h3>Run summary</h3>\n<pre id=\"run-summary\">" + EscapeHtml(options.run_summary) + "</pre>\n";
  return html + "</section>\n";
}

std::string SettingsSection(const ReportData& data) {
  std::string html = "<section id=\"settings\"><h2>Effective settings</h2>\n";
  if (data.files->settings.empty()) return html + "<p class=\"note\">No settings_used.yaml.</p></section>\n";
  std::vector<std::vector<HtmlCell>> rows;
  for (const auto& [key, value] : data.files->settings) rows.push_back({{key}, {value}});
  return html + "<p>settings_used.yaml: every key with its value after the flags.</p>\n" +
         HtmlTable({"key", "value"}, rows, "settings") + "</section>\n";
}

}  // namespace esdslam
