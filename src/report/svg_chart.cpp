#include "report/svg_chart.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "common/error.h"
#include "report/html.h"

namespace esdslam {
namespace {

constexpr double kLeft = 70, kRight = 20, kTop = 44, kBottom = 46;  // margins, px

// A 1-2-5 step that gives about `count` ticks over span (> 0).
double NiceStep(double span, double count) {
  const double raw = span / count;
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  for (double factor : {1.0, 2.0, 5.0}) {
    if (factor * magnitude >= raw * (1 - 1e-9)) return factor * magnitude;
  }
  return 10.0 * magnitude;
}

std::vector<double> Ticks(double min, double max, double step) {
  std::vector<double> ticks;
  for (double t = std::ceil(min / step - 1e-9) * step; t <= max + 1e-9 * step; t += step)
    ticks.push_back(std::abs(t) < 1e-9 * step ? 0.0 : t);
  return ticks;
}

std::string Label(double value) { return fmt::format("{:.4g}", value); }

// [min, max] of the finite values of one coordinate over all series.
std::pair<double, double> Range(const std::vector<ChartSeries>& series, bool use_x) {
  double lo = INFINITY, hi = -INFINITY;
  for (const ChartSeries& s : series) {
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      const double v = use_x ? s.x[i] : s.y[i];
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  }
  return {lo, hi};
}

std::string Polylines(const ChartSeries& s, const ChartAxes& axes) {
  std::string text, points;
  const std::string style = fmt::format("fill=\"none\" stroke=\"{}\" stroke-width=\"1.3\"{}", EscapeHtml(s.colour),
                                        s.dashed ? " stroke-dasharray=\"5,4\"" : "");
  auto flush = [&] {
    if (!points.empty()) text += "<polyline " + style + " points=\"" + points + "\"/>\n";
    points.clear();
  };
  for (std::size_t i = 0; i < s.x.size(); ++i) {
    if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) {
      flush();
      continue;
    }
    points += fmt::format("{}{:.1f},{:.1f}", points.empty() ? "" : " ", axes.PixelX(s.x[i]), axes.PixelY(s.y[i]));
  }
  flush();
  return text;
}

std::string AxesSvg(const ChartAxes& a, const ChartOptions& options) {
  std::string text;
  for (double x : Ticks(a.min_x, a.max_x, NiceStep(a.max_x - a.min_x, 10))) {
    const double px = a.PixelX(x);
    text += fmt::format("<line x1=\"{0:.1f}\" y1=\"{1:.1f}\" x2=\"{0:.1f}\" y2=\"{2:.1f}\" stroke=\"#e4e4e4\"/>"
                        "<text x=\"{0:.1f}\" y=\"{3:.1f}\" font-size=\"11\" text-anchor=\"middle\">{4}</text>\n",
                        px, a.top_px, a.bottom_px, a.bottom_px + 14, Label(x));
  }
  for (double y : Ticks(a.min_y, a.max_y, NiceStep(a.max_y - a.min_y, 5))) {
    const double py = a.PixelY(y);
    text += fmt::format("<line x1=\"{1:.1f}\" y1=\"{0:.1f}\" x2=\"{2:.1f}\" y2=\"{0:.1f}\" stroke=\"#e4e4e4\"/>"
                        "<text x=\"{3:.1f}\" y=\"{4:.1f}\" font-size=\"11\" text-anchor=\"end\">{5}</text>\n",
                        py, a.left_px, a.right_px, a.left_px - 5, py + 4, Label(y));
  }
  text += fmt::format("<rect x=\"{:.1f}\" y=\"{:.1f}\" width=\"{:.1f}\" height=\"{:.1f}\" fill=\"none\" stroke=\"#444\"/>\n",
                      a.left_px, a.top_px, a.right_px - a.left_px, a.bottom_px - a.top_px);
  text += fmt::format("<text x=\"{:.1f}\" y=\"{}\" font-size=\"12\" text-anchor=\"middle\">{}</text>\n",
                      0.5 * (a.left_px + a.right_px), options.height_px - 8, EscapeHtml(options.x_label));
  const double mid_y = 0.5 * (a.top_px + a.bottom_px);
  text += fmt::format("<text x=\"14\" y=\"{0:.1f}\" font-size=\"12\" text-anchor=\"middle\" "
                      "transform=\"rotate(-90 14 {0:.1f})\">{1}</text>\n",
                      mid_y, EscapeHtml(options.y_label));
  return text;
}

std::string LegendSvg(const std::vector<ChartSeries>& series, const ChartOptions& options) {
  std::string text = fmt::format("<text x=\"{}\" y=\"16\" font-size=\"14\" font-weight=\"bold\">{}</text>\n", kLeft,
                                 EscapeHtml(options.title));
  double x = kLeft;
  for (const ChartSeries& s : series) {
    text += fmt::format("<line x1=\"{0:.1f}\" y1=\"30\" x2=\"{1:.1f}\" y2=\"30\" stroke=\"{2}\" stroke-width=\"2\"{3}/>"
                        "<text x=\"{4:.1f}\" y=\"34\" font-size=\"12\">{5}</text>\n",
                        x, x + 22, EscapeHtml(s.colour), s.dashed ? " stroke-dasharray=\"5,4\"" : "", x + 26,
                        EscapeHtml(s.label));
    x += 40 + 7.0 * static_cast<double>(s.label.size());
  }
  if (!options.shaded_x.empty()) {
    text += fmt::format("<rect x=\"{:.1f}\" y=\"24\" width=\"22\" height=\"12\" fill=\"#f3c9a5\"/>"
                        "<text x=\"{:.1f}\" y=\"34\" font-size=\"12\">{}</text>\n",
                        x, x + 26, EscapeHtml(options.shaded_label));
  }
  return text;
}

std::string ShadingSvg(const ChartAxes& a, const ChartOptions& options) {
  std::string text;
  for (const auto& [begin, end] : options.shaded_x) {
    const double x0 = std::clamp(a.PixelX(begin), a.left_px, a.right_px);
    const double x1 = std::clamp(a.PixelX(end), a.left_px, a.right_px);
    if (x1 <= x0) continue;
    text += fmt::format("<rect class=\"shade\" x=\"{:.1f}\" y=\"{:.1f}\" width=\"{:.1f}\" height=\"{:.1f}\" "
                        "fill=\"#f3c9a5\"/>\n",
                        x0, a.top_px, std::max(0.5, x1 - x0), a.bottom_px - a.top_px);
  }
  return text;
}

}  // namespace

void ChartOptions::Check() const {
  if (width_px < 200 || height_px < 120 || width_px > 10000 || height_px > 10000)
    throw Error(fmt::format("chart size {}x{} px: expected 200..10000 x 120..10000", width_px, height_px));
  for (const auto& [begin, end] : shaded_x)
    if (!(begin <= end)) throw Error(fmt::format("chart shading [{}, {}]: begin must not exceed end", begin, end));
}

ChartAxes MakeChartAxes(const std::vector<ChartSeries>& series, const ChartOptions& options) {
  for (const ChartSeries& s : series)
    if (s.x.size() != s.y.size())
      throw Error(fmt::format("chart series '{}': {} x values for {} y values", s.label, s.x.size(), s.y.size()));
  auto [min_x, max_x] = Range(series, true);
  auto [min_y, max_y] = Range(series, false);
  if (!(min_x <= max_x)) throw Error("chart '" + options.title + "': no finite point to plot");
  if (max_x == min_x) max_x = min_x + 1;
  if (options.y_from_zero && min_y >= 0) min_y = 0;
  if (max_y == min_y) max_y = min_y + 1;
  const double step = NiceStep(max_y - min_y, 5);
  ChartAxes axes;
  axes.min_x = min_x;
  axes.max_x = max_x;
  axes.min_y = std::floor(min_y / step + 1e-9) * step;
  axes.max_y = std::ceil(max_y / step - 1e-9) * step;
  axes.left_px = kLeft;
  axes.right_px = options.width_px - kRight;
  axes.top_px = kTop;
  axes.bottom_px = options.height_px - kBottom;
  return axes;
}

std::string LineChartSvg(const std::vector<ChartSeries>& series, const ChartOptions& options) {
  options.Check();
  const ChartAxes axes = MakeChartAxes(series, options);
  std::string text = fmt::format("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{0}\" height=\"{1}\" "
                                 "viewBox=\"0 0 {0} {1}\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n",
                                 options.width_px, options.height_px);
  text += ShadingSvg(axes, options) + AxesSvg(axes, options);
  for (const ChartSeries& s : series) text += Polylines(s, axes);
  return text + LegendSvg(series, options) + "</svg>\n";
}

}  // namespace esdslam
