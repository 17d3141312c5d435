#include "synth/texture.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

namespace esdslam {
namespace {

constexpr int kShift = 4;  // sub-texel precision of the drawing calls (1/16 texel)
constexpr double kSubTexel = 1 << kShift;

cv::Scalar RandomColour(double colour_probability, std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::uniform_int_distribution<int> level(0, 255);
  if (unit(rng) < colour_probability) return cv::Scalar(level(rng), level(rng), level(rng));
  const int grey = level(rng);
  return cv::Scalar(grey, grey, grey);
}

cv::Point ToFixed(double x, double y) {
  return cv::Point(static_cast<int>(std::lround(x * kSubTexel)), static_cast<int>(std::lround(y * kSubTexel)));
}

// Draws one random shape of about `size_px` texels centred at (cx, cy).
void DrawShape(cv::Mat& image, double cx, double cy, double size_px, const cv::Scalar& colour, std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double w = size_px * (0.5 + unit(rng));
  const double h = size_px * (0.5 + unit(rng));
  const double kind = unit(rng);
  if (kind < 0.45) {  // axis-aligned rectangle: the strongest corners
    cv::rectangle(image, ToFixed(cx - w / 2, cy - h / 2), ToFixed(cx + w / 2, cy + h / 2), colour, cv::FILLED,
                  cv::LINE_AA, kShift);
    return;
  }
  if (kind < 0.65) {  // ellipse
    cv::ellipse(image, ToFixed(cx, cy), cv::Size(static_cast<int>(w / 2 * kSubTexel), static_cast<int>(h / 2 * kSubTexel)),
                unit(rng) * 180.0, 0, 360, colour, cv::FILLED, cv::LINE_AA, kShift);
    return;
  }
  // rotated rectangle or triangle
  const double angle = unit(rng) * M_PI;
  const double c = std::cos(angle), s = std::sin(angle);
  std::vector<cv::Point> corners;
  const int n = kind < 0.85 ? 4 : 3;
  for (int i = 0; i < n; ++i) {
    double x, y;
    if (n == 4) {
      x = (i == 0 || i == 3 ? -w : w) / 2;
      y = (i < 2 ? -h : h) / 2;
    } else {
      const double a = 2 * M_PI * i / 3 + (unit(rng) - 0.5);
      x = w / 2 * std::cos(a);
      y = h / 2 * std::sin(a);
    }
    corners.push_back(ToFixed(cx + c * x - s * y, cy + s * x + c * y));
  }
  cv::fillConvexPoly(image, corners, colour, cv::LINE_AA, kShift);
}

void DrawLayers(cv::Mat& image, double texel_m, const TextureStyle& style, std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double area_px = static_cast<double>(image.cols) * image.rows;
  for (std::size_t layer = 0; layer < style.scales_m.size(); ++layer) {
    const double size_px = style.scales_m[layer] / texel_m;
    const double coverage = layer < style.coverage.size() ? style.coverage[layer] : 0.2;
    const int count = static_cast<int>(std::ceil(coverage * area_px / (size_px * size_px)));
    for (int i = 0; i < count; ++i) {
      const double cx = unit(rng) * image.cols;
      const double cy = unit(rng) * image.rows;
      DrawShape(image, cx, cy, size_px, RandomColour(style.colour_probability, rng), rng);
    }
  }
}

void DrawPosters(cv::Mat& image, double texel_m, const TextureStyle& style, std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double area_m2 = image.cols * texel_m * image.rows * texel_m;
  const int count = static_cast<int>(std::floor(style.posters_per_m2 * area_m2 + unit(rng)));
  TextureStyle fine;
  fine.base_bgr = cv::Vec3b(static_cast<uchar>(unit(rng) * 255), static_cast<uchar>(unit(rng) * 255),
                            static_cast<uchar>(unit(rng) * 255));
  fine.scales_m = {0.12, 0.06, 0.035};
  fine.coverage = {0.6, 0.5, 0.35};
  fine.colour_probability = 0.7;
  for (int i = 0; i < count; ++i) {
    const int w = std::min(image.cols, static_cast<int>((0.25 + 0.35 * unit(rng)) / texel_m));
    const int h = std::min(image.rows, static_cast<int>((0.25 + 0.35 * unit(rng)) / texel_m));
    const int x = static_cast<int>(unit(rng) * (image.cols - w));
    const int y = static_cast<int>(unit(rng) * (image.rows - h));
    cv::Mat roi = image(cv::Rect(x, y, w, h));
    roi.setTo(RandomColour(0.5, rng));
    DrawLayers(roi, texel_m, fine, rng);
    cv::rectangle(image, cv::Rect(x, y, w, h), cv::Scalar(20, 20, 20), std::max(2, static_cast<int>(0.01 / texel_m)));
  }
}

}  // namespace

cv::Mat MakeTexture(double width_m, double height_m, double texel_m, const TextureStyle& style, std::mt19937& rng) {
  const int cols = std::max(2, static_cast<int>(std::ceil(width_m / texel_m)));
  const int rows = std::max(2, static_cast<int>(std::ceil(height_m / texel_m)));
  cv::Mat image(rows, cols, CV_8UC3, cv::Scalar(style.base_bgr[0], style.base_bgr[1], style.base_bgr[2]));
  DrawLayers(image, texel_m, style, rng);
  DrawPosters(image, texel_m, style, rng);
  return image;
}

}  // namespace esdslam
