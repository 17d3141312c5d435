#pragma once
// Line charts over time as inline SVG for the run report (report/run_report.h): one or more
// series sharing an x axis (seconds), a y axis with 1-2-5 ticks, a legend, and x intervals
// shaded behind the lines (e.g. the frames where people cover most of the image).

#include <string>
#include <utility>
#include <vector>

namespace esdslam {

struct ChartSeries {
  std::string label;
  std::string colour;  // CSS colour
  std::vector<double> x, y;  // same length; non-finite y values break the line
  bool dashed = false;
};

struct ChartOptions {
  std::string title;
  std::string x_label = "time [s]";
  std::string y_label;
  int width_px = 900, height_px = 260;  // at least 200 x 120 (Check)
  // [begin, end] ranges of x shaded grey behind the series, with this legend text.
  std::vector<std::pair<double, double>> shaded_x;
  std::string shaded_label;
  bool y_from_zero = true;  // y axis starts at 0 when all values are >= 0
  void Check() const;       // throws Error
};

// Data -> pixel mapping of a chart (the plot area inside the margins, y up).
struct ChartAxes {
  double min_x = 0, max_x = 1, min_y = 0, max_y = 1;
  double left_px = 0, right_px = 1, top_px = 0, bottom_px = 1;
  double PixelX(double x) const { return left_px + (x - min_x) / (max_x - min_x) * (right_px - left_px); }
  double PixelY(double y) const { return bottom_px - (y - min_y) / (max_y - min_y) * (bottom_px - top_px); }
};

// The axes a chart of these series gets (ranges padded to ticks; a flat series gets a unit range).
// Throws Error when no series has a finite point or a series' x and y differ in length.
ChartAxes MakeChartAxes(const std::vector<ChartSeries>& series, const ChartOptions& options);

// One standalone <svg> element. Throws Error as MakeChartAxes and ChartOptions::Check.
std::string LineChartSvg(const std::vector<ChartSeries>& series, const ChartOptions& options);

}  // namespace esdslam
