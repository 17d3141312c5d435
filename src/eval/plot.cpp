#include "eval/plot.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "common/error.h"

namespace esdslam {
namespace {

constexpr int kWidth = 800, kHeight = 800;
constexpr int kMarginLeft = 70, kMarginRight = 30, kMarginTop = 60, kMarginBottom = 60;

// World X-Y (metres) -> image pixels, equal scale on both axes, y up.
struct PlotFrame {
  double min_x = 0, max_x = 0, min_y = 0, max_y = 0;
  double pixels_per_metre = 1;
  double tick_m = 1;  // a 1-2-5 step giving about 4-8 ticks

  cv::Point2d ToPixel(double x, double y) const {
    return {kMarginLeft + (x - min_x) * pixels_per_metre, kHeight - kMarginBottom - (y - min_y) * pixels_per_metre};
  }
};

double NiceStep(double span) {
  const double raw = span / 8.0;
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  for (double factor : {1.0, 2.0, 5.0, 10.0}) {
    if (factor * magnitude >= raw) return factor * magnitude;
  }
  return 10.0 * magnitude;
}

PlotFrame MakeFrame(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  PlotFrame frame;
  frame.min_x = frame.min_y = 1e300;
  frame.max_x = frame.max_y = -1e300;
  for (const auto* points : {&a, &b}) {
    for (const Vec3& p : *points) {
      frame.min_x = std::min(frame.min_x, p.x());
      frame.max_x = std::max(frame.max_x, p.x());
      frame.min_y = std::min(frame.min_y, p.y());
      frame.max_y = std::max(frame.max_y, p.y());
    }
  }
  const double span = std::max({frame.max_x - frame.min_x, frame.max_y - frame.min_y, 0.05});
  const double pad = 0.05 * span;
  const double cx = 0.5 * (frame.min_x + frame.max_x), cy = 0.5 * (frame.min_y + frame.max_y);
  frame.min_x = cx - 0.5 * span - pad;
  frame.max_x = cx + 0.5 * span + pad;
  frame.min_y = cy - 0.5 * span - pad;
  frame.max_y = cy + 0.5 * span + pad;
  const double usable = std::min(kWidth - kMarginLeft - kMarginRight, kHeight - kMarginTop - kMarginBottom);
  frame.pixels_per_metre = usable / (span + 2 * pad);
  frame.tick_m = NiceStep(span + 2 * pad);
  return frame;
}

std::vector<double> Ticks(double min, double max, double step) {
  std::vector<double> ticks;
  for (double t = std::ceil(min / step) * step; t <= max + 1e-12; t += step) ticks.push_back(std::abs(t) < 1e-12 ? 0 : t);
  return ticks;
}

std::string Label(double value) { return fmt::format("{:g}", value); }

// ---- SVG ----

std::string SvgPolyline(const PlotFrame& frame, const std::vector<Vec3>& points, const char* colour, double width) {
  std::string text =
      fmt::format("<polyline fill=\"none\" stroke=\"{}\" stroke-width=\"{}\" points=\"", colour, width);
  for (const Vec3& p : points) {
    const cv::Point2d q = frame.ToPixel(p.x(), p.y());
    text += fmt::format("{:.1f},{:.1f} ", q.x, q.y);
  }
  return text + "\"/>\n";
}

std::string SvgAxes(const PlotFrame& frame) {
  std::string text;
  const cv::Point2d lo = frame.ToPixel(frame.min_x, frame.min_y), hi = frame.ToPixel(frame.max_x, frame.max_y);
  text += fmt::format("<rect x=\"{:.1f}\" y=\"{:.1f}\" width=\"{:.1f}\" height=\"{:.1f}\" fill=\"none\" stroke=\"black\"/>\n",
                      lo.x, hi.y, hi.x - lo.x, lo.y - hi.y);
  for (double x : Ticks(frame.min_x, frame.max_x, frame.tick_m)) {
    const double px = frame.ToPixel(x, 0).x;
    text += fmt::format("<line x1=\"{0:.1f}\" y1=\"{1:.1f}\" x2=\"{0:.1f}\" y2=\"{2:.1f}\" stroke=\"#ddd\"/>\n", px, lo.y, hi.y);
    text += fmt::format("<text x=\"{:.1f}\" y=\"{:.1f}\" font-size=\"12\" text-anchor=\"middle\">{}</text>\n", px,
                        lo.y + 16, Label(x));
  }
  for (double y : Ticks(frame.min_y, frame.max_y, frame.tick_m)) {
    const double py = frame.ToPixel(0, y).y;
    text += fmt::format("<line x1=\"{1:.1f}\" y1=\"{0:.1f}\" x2=\"{2:.1f}\" y2=\"{0:.1f}\" stroke=\"#ddd\"/>\n", py, lo.x, hi.x);
    text += fmt::format("<text x=\"{:.1f}\" y=\"{:.1f}\" font-size=\"12\" text-anchor=\"end\">{}</text>\n", lo.x - 6,
                        py + 4, Label(y));
  }
  text += fmt::format("<text x=\"{:.1f}\" y=\"{}\" font-size=\"14\" text-anchor=\"middle\">x [m]</text>\n",
                      0.5 * (lo.x + hi.x), kHeight - 15);
  text += fmt::format("<text x=\"18\" y=\"{:.1f}\" font-size=\"14\" transform=\"rotate(-90 18 {:.1f})\" "
                      "text-anchor=\"middle\">y [m]</text>\n", 0.5 * (lo.y + hi.y), 0.5 * (lo.y + hi.y));
  return text;
}

std::string SvgLegendAndScale(const PlotFrame& frame) {
  std::string text;
  text += "<line x1=\"80\" y1=\"20\" x2=\"110\" y2=\"20\" stroke=\"black\" stroke-width=\"2\"/>"
          "<text x=\"115\" y=\"25\" font-size=\"14\">ground truth</text>\n";
  text += "<line x1=\"240\" y1=\"20\" x2=\"270\" y2=\"20\" stroke=\"#1f77b4\" stroke-width=\"2\"/>"
          "<text x=\"275\" y=\"25\" font-size=\"14\">estimate (aligned)</text>\n";
  const double bar_px = frame.tick_m * frame.pixels_per_metre;
  text += fmt::format("<line x1=\"{0}\" y1=\"40\" x2=\"{1:.1f}\" y2=\"40\" stroke=\"black\" stroke-width=\"3\"/>"
                      "<text x=\"{2:.1f}\" y=\"45\" font-size=\"14\">{3} m</text>\n",
                      kWidth - kMarginRight - 60 - bar_px, kWidth - kMarginRight - 60.0, kWidth - kMarginRight - 55.0,
                      Label(frame.tick_m));
  return text;
}

std::string SvgText(const PlotFrame& frame, const std::vector<Vec3>& gt, const std::vector<Vec3>& est) {
  return fmt::format("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{0}\" height=\"{1}\" viewBox=\"0 0 {0} {1}\">\n",
                     kWidth, kHeight) +
         "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n" + SvgAxes(frame) +
         SvgPolyline(frame, est, "#1f77b4", 1.2) + SvgPolyline(frame, gt, "black", 2) + SvgLegendAndScale(frame) +
         "</svg>\n";
}

void WriteSvg(const PlotFrame& frame, const std::vector<Vec3>& gt, const std::vector<Vec3>& est,
              const std::string& path) {
  std::ofstream out(path);
  out << SvgText(frame, gt, est);
  out.close();
  if (!out) throw Error("cannot write plot " + path);
}

// ---- PNG ----

void DrawPolyline(cv::Mat& image, const PlotFrame& frame, const std::vector<Vec3>& points, const cv::Scalar& colour,
                  int thickness) {
  std::vector<cv::Point> pixels;
  for (const Vec3& p : points) pixels.push_back(frame.ToPixel(p.x(), p.y()));
  if (pixels.size() == 1) cv::circle(image, pixels[0], 2, colour, cv::FILLED, cv::LINE_AA);
  cv::polylines(image, pixels, false, colour, thickness, cv::LINE_AA);
}

void DrawAxes(cv::Mat& image, const PlotFrame& frame) {
  const cv::Scalar black(0, 0, 0), grey(220, 220, 220);
  const cv::Point2d lo = frame.ToPixel(frame.min_x, frame.min_y), hi = frame.ToPixel(frame.max_x, frame.max_y);
  for (double x : Ticks(frame.min_x, frame.max_x, frame.tick_m)) {
    const int px = static_cast<int>(std::lround(frame.ToPixel(x, 0).x));
    cv::line(image, {px, int(lo.y)}, {px, int(hi.y)}, grey);
    cv::putText(image, Label(x), {px - 12, int(lo.y) + 18}, cv::FONT_HERSHEY_SIMPLEX, 0.4, black, 1, cv::LINE_AA);
  }
  for (double y : Ticks(frame.min_y, frame.max_y, frame.tick_m)) {
    const int py = static_cast<int>(std::lround(frame.ToPixel(0, y).y));
    cv::line(image, {int(lo.x), py}, {int(hi.x), py}, grey);
    cv::putText(image, Label(y), {int(lo.x) - 45, py + 4}, cv::FONT_HERSHEY_SIMPLEX, 0.4, black, 1, cv::LINE_AA);
  }
  cv::rectangle(image, cv::Point(int(lo.x), int(hi.y)), cv::Point(int(hi.x), int(lo.y)), black);
  cv::putText(image, "x [m]", {int(0.5 * (lo.x + hi.x)) - 20, kHeight - 15}, cv::FONT_HERSHEY_SIMPLEX, 0.5, black, 1,
              cv::LINE_AA);
  cv::putText(image, "y [m]", {5, int(hi.y) - 10}, cv::FONT_HERSHEY_SIMPLEX, 0.5, black, 1, cv::LINE_AA);
}

void DrawLegendAndScale(cv::Mat& image, const PlotFrame& frame, const cv::Scalar& gt_colour,
                        const cv::Scalar& est_colour) {
  const cv::Scalar black(0, 0, 0);
  cv::line(image, {80, 20}, {110, 20}, gt_colour, 2);
  cv::putText(image, "ground truth", {115, 25}, cv::FONT_HERSHEY_SIMPLEX, 0.5, black, 1, cv::LINE_AA);
  cv::line(image, {240, 20}, {270, 20}, est_colour, 2);
  cv::putText(image, "estimate (aligned)", {275, 25}, cv::FONT_HERSHEY_SIMPLEX, 0.5, black, 1, cv::LINE_AA);
  const int bar_px = static_cast<int>(std::lround(frame.tick_m * frame.pixels_per_metre));
  const int right = kWidth - kMarginRight - 60;
  cv::line(image, {right - bar_px, 40}, {right, 40}, black, 3);
  cv::putText(image, Label(frame.tick_m) + " m", {right + 5, 45}, cv::FONT_HERSHEY_SIMPLEX, 0.5, black, 1,
              cv::LINE_AA);
}

void WritePng(const PlotFrame& frame, const std::vector<Vec3>& gt, const std::vector<Vec3>& est,
              const std::string& path) {
  cv::Mat image(kHeight, kWidth, CV_8UC3, cv::Scalar(255, 255, 255));
  const cv::Scalar gt_colour(0, 0, 0), est_colour(180, 119, 31);  // BGR
  DrawAxes(image, frame);
  DrawPolyline(image, frame, est, est_colour, 1);
  DrawPolyline(image, frame, gt, gt_colour, 2);  // on top: the reference stays visible
  DrawLegendAndScale(image, frame, gt_colour, est_colour);
  bool ok = false;
  try {
    ok = cv::imwrite(path, image);
  } catch (const cv::Exception&) {
    ok = false;
  }
  if (!ok) throw Error("cannot write plot " + path);
}

}  // namespace

void PlotTrajectoriesXY(const std::vector<Vec3>& groundtruth, const std::vector<Vec3>& estimate,
                        const std::string& path) {
  if (groundtruth.empty() && estimate.empty()) throw Error("nothing to plot");
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char c) { return std::tolower(c); });
  if (extension != ".svg" && extension != ".png") throw Error("plot file must end in .svg or .png: " + path);
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  std::error_code ignored;
  if (!parent.empty()) std::filesystem::create_directories(parent, ignored);
  const PlotFrame frame = MakeFrame(groundtruth, estimate);
  if (extension == ".svg") {
    WriteSvg(frame, groundtruth, estimate, path);
  } else {
    WritePng(frame, groundtruth, estimate, path);
  }
}

std::string TrajectoriesXYSvg(const std::vector<Vec3>& groundtruth, const std::vector<Vec3>& estimate) {
  if (groundtruth.empty() && estimate.empty()) throw Error("nothing to plot");
  return SvgText(MakeFrame(groundtruth, estimate), groundtruth, estimate);
}

}  // namespace esdslam
