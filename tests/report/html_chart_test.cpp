// The HTML and SVG pieces of the run report: escaping, base64, tables and line charts (the
// pixels of the points follow the inputs, the markup is well formed).
#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "common/error.h"
#include "report/html.h"
#include "report/markup.h"
#include "report/svg_chart.h"

namespace esdslam {
namespace {

using testing::CheckMarkup;
using testing::CountOf;

std::vector<std::uint8_t> Bytes(const std::string& text) { return {text.begin(), text.end()}; }

TEST(Html, Base64MatchesTheRfcVectors) {
  EXPECT_EQ(Base64Encode(Bytes("")), "");
  EXPECT_EQ(Base64Encode(Bytes("f")), "Zg==");
  EXPECT_EQ(Base64Encode(Bytes("fo")), "Zm8=");
  EXPECT_EQ(Base64Encode(Bytes("foo")), "Zm9v");
  EXPECT_EQ(Base64Encode(Bytes("foob")), "Zm9vYg==");
  EXPECT_EQ(Base64Encode(Bytes("fooba")), "Zm9vYmE=");
  EXPECT_EQ(Base64Encode(Bytes("foobar")), "Zm9vYmFy");
  EXPECT_EQ(Base64Encode({0xff, 0xfe, 0x00}), "//4A");
}

TEST(Html, EscapesMarkupCharacters) {
  EXPECT_EQ(EscapeHtml("a<b>&\"c\"'d'"), "a&lt;b&gt;&amp;&quot;c&quot;&#39;d&#39;");
  EXPECT_EQ(EscapeHtml("plain 1.5 m"), "plain 1.5 m");
}

TEST(Html, TableCarriesMetricNamesAndEscapesCells) {
  const std::string html = HtmlTable({"name", "value"}, {{{"ate<rmse>"}, {"0.0123", "ate_rmse"}}, {{"only"}}}, "t");
  EXPECT_EQ(CheckMarkup(html), "");
  EXPECT_NE(html.find("<table class=\"t\">"), std::string::npos);
  EXPECT_NE(html.find("<td>ate&lt;rmse&gt;</td>"), std::string::npos);
  EXPECT_EQ(testing::MetricText(html, "ate_rmse"), "0.0123");
  EXPECT_EQ(CountOf(html, "<tr>"), 3u);   // header + 2 rows
  EXPECT_EQ(CountOf(html, "<td"), 4u);    // the short row is padded
}

TEST(Html, PngImageIsADataUrl) {
  const std::string tag = PngImageTag({0x89, 'P', 'N', 'G'}, "a \"frame\"", 320);
  EXPECT_EQ(tag, "<img width=\"320\" alt=\"a &quot;frame&quot;\" src=\"data:image/png;base64,iVBORw==\"/>");
}

// The points of every polyline, as pixel pairs.
std::vector<std::vector<std::pair<double, double>>> Polylines(const std::string& svg) {
  std::vector<std::vector<std::pair<double, double>>> lines;
  for (std::size_t at = svg.find("<polyline"); at != std::string::npos; at = svg.find("<polyline", at + 1)) {
    const std::size_t begin = svg.find("points=\"", at) + 8;
    const std::string points = svg.substr(begin, svg.find('"', begin) - begin);
    std::vector<std::pair<double, double>> line;
    std::size_t pos = 0;
    while (pos < points.size()) {
      std::size_t next = points.find(' ', pos);
      if (next == std::string::npos) next = points.size();
      const std::string pair = points.substr(pos, next - pos);
      const std::size_t comma = pair.find(',');
      line.emplace_back(std::stod(pair.substr(0, comma)), std::stod(pair.substr(comma + 1)));
      pos = next + 1;
    }
    lines.push_back(line);
  }
  return lines;
}

TEST(SvgChart, PointsFollowTheDataAndTheAxesEndOnTicks) {
  ChartSeries series{"error", "#d62728", {0, 2, 5, 10}, {0.5, 3.7, 1.0, 2.0}};
  ChartOptions options;
  options.title = "t";
  options.y_label = "error [m]";
  const ChartAxes axes = MakeChartAxes({series}, options);
  EXPECT_DOUBLE_EQ(axes.min_x, 0);
  EXPECT_DOUBLE_EQ(axes.max_x, 10);
  EXPECT_DOUBLE_EQ(axes.min_y, 0);  // y_from_zero with non-negative values
  EXPECT_DOUBLE_EQ(axes.max_y, 4);  // 3.7 rounded up to the step of 1
  EXPECT_DOUBLE_EQ(axes.PixelX(0), axes.left_px);
  EXPECT_DOUBLE_EQ(axes.PixelX(10), axes.right_px);
  EXPECT_DOUBLE_EQ(axes.PixelY(0), axes.bottom_px);
  EXPECT_DOUBLE_EQ(axes.PixelY(4), axes.top_px);

  const std::string svg = LineChartSvg({series}, options);
  EXPECT_EQ(CheckMarkup(svg), "");
  const auto lines = Polylines(svg);
  ASSERT_EQ(lines.size(), 1u);
  ASSERT_EQ(lines[0].size(), series.x.size());
  for (std::size_t i = 0; i < series.x.size(); ++i) {
    EXPECT_NEAR(lines[0][i].first, axes.PixelX(series.x[i]), 0.051);
    EXPECT_NEAR(lines[0][i].second, axes.PixelY(series.y[i]), 0.051);
  }
  EXPECT_NE(svg.find(">error [m]</text>"), std::string::npos);
}

TEST(SvgChart, NonFiniteValuesBreakTheLineAndShadingIsDrawn) {
  ChartSeries series{"a", "blue", {0, 1, 2, 3, 4}, {1, 2, NAN, 2, 1}};
  ChartOptions options;
  options.shaded_x = {{0.5, 1.5}, {3.0, 3.5}};
  options.shaded_label = "crowded";
  const std::string svg = LineChartSvg({series}, options);
  EXPECT_EQ(CheckMarkup(svg), "");
  const auto lines = Polylines(svg);
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0].size(), 2u);
  EXPECT_EQ(lines[1].size(), 2u);
  EXPECT_EQ(CountOf(svg, "class=\"shade\""), 2u);
  EXPECT_NE(svg.find(">crowded</text>"), std::string::npos);
  const ChartAxes axes = MakeChartAxes({series}, options);
  EXPECT_NE(svg.find(fmt::format("class=\"shade\" x=\"{:.1f}\"", axes.PixelX(0.5))), std::string::npos);
}

TEST(SvgChart, RejectsBadInput) {
  ChartOptions options;
  EXPECT_THROW(LineChartSvg({{"a", "red", {0, 1}, {1}}}, options), Error);          // sizes differ
  EXPECT_THROW(LineChartSvg({{"a", "red", {0, 1}, {NAN, NAN}}}, options), Error);  // nothing finite
  EXPECT_THROW(LineChartSvg({}, options), Error);
  options.width_px = 10;
  EXPECT_THROW(LineChartSvg({{"a", "red", {0, 1}, {1, 2}}}, options), Error);
  options.width_px = 900;
  options.shaded_x = {{2, 1}};
  EXPECT_THROW(LineChartSvg({{"a", "red", {0, 1}, {1, 2}}}, options), Error);
}

TEST(SvgChart, AFlatSeriesGetsARange) {
  const ChartAxes axes = MakeChartAxes({{"a", "red", {3, 3}, {-2, -2}}}, ChartOptions{});
  EXPECT_LT(axes.min_x, axes.max_x);
  EXPECT_LT(axes.min_y, axes.max_y);
  EXPECT_LE(axes.min_y, -2);
  EXPECT_GE(axes.max_y, -2);
}

}  // namespace
}  // namespace esdslam
