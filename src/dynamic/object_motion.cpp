#include "dynamic/object_motion.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "common/error.h"

namespace esdslam {
namespace {

// Sums for the least-squares similarity source = [a -b; b a] frame + t.
struct SimilaritySums {
  double n = 0, fx = 0, fy = 0, sx = 0, sy = 0, ff = 0, dot = 0, cross = 0;
  void Add(double x, double y, double u, double v) {
    n += 1;
    fx += x;
    fy += y;
    sx += u;
    sy += v;
    ff += x * x + y * y;
    dot += x * u + y * v;
    cross += x * v - y * u;
  }
  // False when degenerate (fewer than 2 distinct points).
  bool Solve(cv::Matx23d* source_from_frame) const {
    if (n < 2) return false;
    const double mfx = fx / n, mfy = fy / n, msx = sx / n, msy = sy / n;
    const double spread = ff - n * (mfx * mfx + mfy * mfy);
    if (spread <= 1e-9) return false;
    const double a = (dot - n * (mfx * msx + mfy * msy)) / spread;
    const double b = (cross - n * (mfx * msy - mfy * msx)) / spread;
    *source_from_frame = cv::Matx23d(a, -b, msx - (a * mfx - b * mfy), b, a, msy - (b * mfx + a * mfy));
    return true;
  }
};

double Residual(const cv::Matx23d& m, const cv::Vec2f& frame, const cv::Vec2f& source) {
  const double u = m(0, 0) * frame[0] + m(0, 1) * frame[1] + m(0, 2) - source[0];
  const double v = m(1, 0) * frame[0] + m(1, 1) * frame[1] + m(1, 2) - source[1];
  return std::sqrt(u * u + v * v);
}

// Calls visit(object id, frame position, source position) for every valid flow pixel whose
// source position lies in an object's interior.
template <typename Visit>
void ForEachInteriorPixel(const SourceObjects& objects, const cv::Mat& frame_pixels, const cv::Mat& source_pixels,
                          const cv::Mat& consistent, Visit visit) {
  const int w = objects.interior_ids.cols, h = objects.interior_ids.rows;
  for (int y = 0; y < source_pixels.rows; ++y) {
    const cv::Vec2f* f = frame_pixels.ptr<cv::Vec2f>(y);
    const cv::Vec2f* s = source_pixels.ptr<cv::Vec2f>(y);
    const float* ok = consistent.ptr<float>(y);
    for (int x = 0; x < source_pixels.cols; ++x) {
      if (ok[x] < 0.5f) continue;
      const int u = static_cast<int>(std::lround(s[x][0])), v = static_cast<int>(std::lround(s[x][1]));
      if (u < 0 || v < 0 || u >= w || v >= h) continue;
      const int id = objects.interior_ids.at<std::uint16_t>(v, u);
      if (id > 0) visit(id, f[x], s[x]);
    }
  }
}

}  // namespace

void ObjectMotionOptions::Check() const {
  auto require = [](bool ok, const char* what) {
    if (!ok) throw Error(fmt::format("ObjectMotionOptions: {}", what));
  };
  require(interior_erosion_px >= 0 && interior_erosion_px <= 100, "interior_erosion_px must be in [0, 100]");
  require(min_component_px >= 1, "min_component_px must be >= 1");
  require(min_fit_pixels >= 3, "min_fit_pixels must be >= 3");
  require(min_inlier_px > 0 && min_inlier_px <= 100, "min_inlier_px must be in (0, 100]");
  require(min_inlier_fraction >= 0 && min_inlier_fraction <= 1, "min_inlier_fraction must be in [0, 1]");
}

SourceObjects FindSourceObjects(const cv::Mat& dynamic_mask, const ObjectMotionOptions& options) {
  CV_Assert(dynamic_mask.type() == CV_8UC1);
  SourceObjects objects;
  cv::Mat labels, stats, centroids;
  const int n = cv::connectedComponentsWithStats(dynamic_mask != 0, labels, stats, centroids, 8, CV_32S);
  std::vector<std::uint16_t> id_of(static_cast<std::size_t>(n), 0);
  for (int label = 1; label < n; ++label) {
    if (stats.at<int>(label, cv::CC_STAT_AREA) < options.min_component_px) continue;
    const cv::Rect box(stats.at<int>(label, cv::CC_STAT_LEFT), stats.at<int>(label, cv::CC_STAT_TOP),
                       stats.at<int>(label, cv::CC_STAT_WIDTH), stats.at<int>(label, cv::CC_STAT_HEIGHT));
    if (objects.boxes.size() < 65535) {
      objects.boxes.push_back(box);
    } else {
      objects.boxes.back() |= box;
    }
    id_of[static_cast<std::size_t>(label)] = static_cast<std::uint16_t>(objects.boxes.size());
  }
  objects.ids = cv::Mat::zeros(dynamic_mask.size(), CV_16U);
  for (int y = 0; y < labels.rows; ++y) {
    const int* in = labels.ptr<int>(y);
    std::uint16_t* out = objects.ids.ptr<std::uint16_t>(y);
    for (int x = 0; x < labels.cols; ++x) out[x] = id_of[static_cast<std::size_t>(in[x])];
  }
  cv::Mat interior;
  const int r = options.interior_erosion_px;
  cv::erode(dynamic_mask != 0, interior, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * r + 1, 2 * r + 1)));
  objects.interior_ids = cv::Mat::zeros(dynamic_mask.size(), CV_16U);
  objects.ids.copyTo(objects.interior_ids, interior);
  return objects;
}

std::vector<ObjectMotion> FitObjectMotions(const SourceObjects& objects, const cv::Mat& frame_pixels,
                                           const cv::Mat& source_pixels, const cv::Mat& consistent,
                                           const ObjectMotionOptions& options) {
  CV_Assert(frame_pixels.type() == CV_32FC2 && source_pixels.type() == CV_32FC2 && consistent.type() == CV_32FC1 &&
            frame_pixels.size() == source_pixels.size() && consistent.size() == source_pixels.size());
  const std::size_t count = objects.boxes.size();
  std::vector<SimilaritySums> first(count), second(count);
  ForEachInteriorPixel(objects, frame_pixels, source_pixels, consistent,
                       [&](int id, const cv::Vec2f& f, const cv::Vec2f& s) { first[id - 1].Add(f[0], f[1], s[0], s[1]); });
  std::vector<ObjectMotion> motions(count);
  std::vector<double> threshold(count, -1.0), squared(count, 0.0);
  std::vector<cv::Matx23d> initial(count);
  for (std::size_t i = 0; i < count; ++i) {
    if (first[i].n < options.min_fit_pixels || !first[i].Solve(&initial[i])) continue;
    threshold[i] = 0;  // RMS of the first fit, below
  }
  ForEachInteriorPixel(objects, frame_pixels, source_pixels, consistent, [&](int id, const cv::Vec2f& f, const cv::Vec2f& s) {
    const double r = Residual(initial[id - 1], f, s);
    squared[id - 1] += r * r;
  });
  for (std::size_t i = 0; i < count; ++i) {
    if (threshold[i] < 0) continue;
    threshold[i] = std::max(options.min_inlier_px, 2.0 * std::sqrt(squared[i] / first[i].n));
    squared[i] = 0;
  }
  ForEachInteriorPixel(objects, frame_pixels, source_pixels, consistent, [&](int id, const cv::Vec2f& f, const cv::Vec2f& s) {
    const std::size_t i = static_cast<std::size_t>(id - 1);
    if (threshold[i] < 0) return;
    const double r = Residual(initial[i], f, s);
    if (r > threshold[i]) return;
    second[i].Add(f[0], f[1], s[0], s[1]);
    squared[i] += r * r;
  });
  for (std::size_t i = 0; i < count; ++i) {
    if (threshold[i] < 0 || second[i].n < options.min_inlier_fraction * first[i].n || second[i].n < options.min_fit_pixels)
      continue;
    ObjectMotion& motion = motions[i];
    motion.fitted = second[i].Solve(&motion.source_from_frame);
    motion.inliers = static_cast<int>(second[i].n);
    motion.rms_px = std::sqrt(squared[i] / second[i].n);
  }
  return motions;
}

cv::Mat DrawObjects(const SourceObjects& objects, const std::vector<ObjectMotion>& motions, cv::Size image_size) {
  cv::Mat out = cv::Mat::zeros(image_size, CV_8U);
  const cv::Rect image(0, 0, image_size.width, image_size.height);
  for (std::size_t i = 0; i < motions.size(); ++i) {
    if (!motions[i].fitted) continue;
    const cv::Matx23d& m = motions[i].source_from_frame;
    cv::Matx23d frame_from_source;
    cv::invertAffineTransform(m, frame_from_source);
    const cv::Rect& box = objects.boxes[i];
    std::vector<cv::Point2f> corners{{float(box.x), float(box.y)}, {float(box.br().x), float(box.y)},
                                     {float(box.x), float(box.br().y)}, {float(box.br().x), float(box.br().y)}};
    cv::transform(corners, corners, frame_from_source);
    const cv::Rect roi = (cv::boundingRect(corners) + cv::Size(2, 2) - cv::Point(1, 1)) & image;
    if (roi.empty()) continue;
    // ROI pixel (u, v) -> source m * (u + roi.x, v + roi.y).
    const cv::Matx23d shifted(m(0, 0), m(0, 1), m(0, 2) + m(0, 0) * roi.x + m(0, 1) * roi.y, m(1, 0), m(1, 1),
                              m(1, 2) + m(1, 0) * roi.x + m(1, 1) * roi.y);
    cv::Mat ids;
    cv::warpAffine(objects.ids, ids, shifted, roi.size(), cv::INTER_NEAREST | cv::WARP_INVERSE_MAP, cv::BORDER_CONSTANT, 0);
    out(roi).setTo(255, ids == static_cast<int>(i + 1));
  }
  return out;
}

}  // namespace esdslam
