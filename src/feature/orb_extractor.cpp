#include "feature/orb_extractor.h"

#include <algorithm>
#include <cmath>

#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include "common/error.h"
#include "feature/orb_distribution.h"

namespace esdslam {
namespace {

constexpr int kPatchSize = 31;    // BRIEF / orientation patch diameter, px at the keypoint's level
constexpr int kHalfPatch = 15;    // radius of the intensity-centroid patch
constexpr int kEdge = 19;         // keypoints keep this distance (level px) from the level border
constexpr double kCellSize = 30;  // FAST cell size (level px) for the threshold fallback

// Images of the scale pyramid; level l is the input resized by 1 / scale_factors[l].
std::vector<cv::Mat> BuildPyramid(const cv::Mat& gray, const std::vector<double>& scale_factors) {
  std::vector<cv::Mat> pyramid(scale_factors.size());
  pyramid[0] = gray;
  for (size_t level = 1; level < pyramid.size(); ++level) {
    const cv::Size size(static_cast<int>(std::lround(gray.cols / scale_factors[level])),
                        static_cast<int>(std::lround(gray.rows / scale_factors[level])));
    if (size.width < 1 || size.height < 1) break;  // remaining levels stay empty
    cv::resize(pyramid[level - 1], pyramid[level], size, 0, 0, cv::INTER_LINEAR);
  }
  return pyramid;
}

// Area of a level image where keypoints may lie (kEdge from the border); empty when too small.
cv::Rect2f DetectionArea(const cv::Mat& level_image) {
  const float width = static_cast<float>(level_image.cols - 2 * kEdge);
  const float height = static_cast<float>(level_image.rows - 2 * kEdge);
  if (width < 1 || height < 1) return {};
  return {static_cast<float>(kEdge), static_cast<float>(kEdge), width, height};
}

bool AllowedByMask(const cv::Mat& mask, const cv::Point2f& level_point, double scale) {
  if (mask.empty()) return true;
  const int u = std::clamp(static_cast<int>(std::lround(level_point.x * scale)), 0, mask.cols - 1);
  const int v = std::clamp(static_cast<int>(std::lround(level_point.y * scale)), 0, mask.rows - 1);
  return mask.at<unsigned char>(v, u) != 0;
}

// The ~30 px cells of a level's detection area, in which FAST falls back to its minimum
// threshold when the initial one finds nothing.
class CellGrid {
 public:
  explicit CellGrid(const cv::Rect2f& area)
      : area_(area),
        cols_(std::max(1, static_cast<int>(area.width / kCellSize))),
        rows_(std::max(1, static_cast<int>(area.height / kCellSize))),
        cell_width_(area.width / cols_),
        cell_height_(area.height / rows_) {}
  int size() const { return cols_ * rows_; }
  // Cell index of a level point, -1 outside the area.
  int CellOf(const cv::Point2f& p) const {
    if (!area_.contains(p)) return -1;
    const int col = std::min(cols_ - 1, static_cast<int>((p.x - area_.x) / cell_width_));
    const int row = std::min(rows_ - 1, static_cast<int>((p.y - area_.y) / cell_height_));
    return row * cols_ + col;
  }
  // Integer pixel rectangle covering a cell.
  cv::Rect PixelRect(int cell) const {
    const float x0 = area_.x + (cell % cols_) * cell_width_, y0 = area_.y + (cell / cols_) * cell_height_;
    const int left = static_cast<int>(std::floor(x0)), top = static_cast<int>(std::floor(y0));
    return {left, top, static_cast<int>(std::ceil(x0 + cell_width_)) - left,
            static_cast<int>(std::ceil(y0 + cell_height_)) - top};
  }

 private:
  cv::Rect2f area_;
  int cols_, rows_;
  float cell_width_, cell_height_;
};

// Whether any level-0 mask pixel under a level rectangle allows keypoints.
bool CellAllowed(const cv::Mat& mask, const cv::Rect& level_rect, double scale) {
  if (mask.empty()) return true;
  const cv::Point top_left(static_cast<int>(level_rect.x * scale), static_cast<int>(level_rect.y * scale));
  const cv::Point bottom_right(static_cast<int>(std::ceil(level_rect.br().x * scale)),
                               static_cast<int>(std::ceil(level_rect.br().y * scale)));
  const cv::Rect rect = cv::Rect(top_left, bottom_right) & cv::Rect(0, 0, mask.cols, mask.rows);
  return !rect.empty() && cv::countNonZero(mask(rect)) > 0;
}

// FAST corners (with non-maximum suppression) of one level inside the detection area and the
// mask: those at the initial threshold, plus, in each cell without any, those at the minimum
// threshold (ORB-SLAM2's per-cell fallback). Row-major within each pass; deterministic.
std::vector<cv::KeyPoint> DetectCorners(const cv::Mat& image, const cv::Mat& mask, double scale,
                                        const OrbOptions& options) {
  const cv::Rect2f area = DetectionArea(image);
  if (area.empty()) return {};
  const CellGrid grid(area);
  std::vector<char> cell_has_corner(grid.size(), 0);
  std::vector<cv::KeyPoint> found, corners;
  cv::FAST(image, found, options.initial_fast_threshold, true);
  for (const cv::KeyPoint& kp : found) {
    const int cell = grid.CellOf(kp.pt);
    if (cell < 0 || !AllowedByMask(mask, kp.pt, scale)) continue;
    cell_has_corner[cell] = 1;
    corners.push_back(kp);
  }
  constexpr int kFastRadius = 3;  // FAST reads a 3 px circle: widen the cell so it can see it
  for (int cell = 0; cell < grid.size(); ++cell) {
    if (cell_has_corner[cell]) continue;
    const cv::Rect rect = grid.PixelRect(cell);
    if (!CellAllowed(mask, rect, scale)) continue;
    const cv::Rect window = (rect + cv::Size(2 * kFastRadius, 2 * kFastRadius)) - cv::Point(kFastRadius, kFastRadius);
    cv::FAST(image(window & cv::Rect(0, 0, image.cols, image.rows)), found, options.min_fast_threshold, true);
    for (cv::KeyPoint kp : found) {
      kp.pt += cv::Point2f(window.tl());
      if (grid.CellOf(kp.pt) == cell && AllowedByMask(mask, kp.pt, scale)) corners.push_back(kp);
    }
  }
  return corners;
}

// Row half-widths of the circular patch of radius kHalfPatch.
std::vector<int> CircleHalfWidths() {
  std::vector<int> half_width(kHalfPatch + 1);
  for (int v = 0; v <= kHalfPatch; ++v)
    half_width[v] = static_cast<int>(std::floor(std::sqrt(kHalfPatch * kHalfPatch - v * v + 0.5)));
  return half_width;
}

// Intensity-centroid orientation (degrees, [0, 360)) of a circular patch around each keypoint.
void ComputeOrientations(const cv::Mat& image, std::vector<cv::KeyPoint>* keypoints) {
  static const std::vector<int> half_width = CircleHalfWidths();
  for (cv::KeyPoint& kp : *keypoints) {
    const int cx = static_cast<int>(std::lround(kp.pt.x)), cy = static_cast<int>(std::lround(kp.pt.y));
    long m10 = 0, m01 = 0;
    const unsigned char* centre_row = image.ptr<unsigned char>(cy);
    for (int u = -kHalfPatch; u <= kHalfPatch; ++u) m10 += u * centre_row[cx + u];
    for (int v = 1; v <= kHalfPatch; ++v) {
      const unsigned char* below = image.ptr<unsigned char>(cy + v);
      const unsigned char* above = image.ptr<unsigned char>(cy - v);
      long row_diff = 0;
      for (int u = -half_width[v]; u <= half_width[v]; ++u) {
        m10 += u * (below[cx + u] + above[cx + u]);
        row_diff += below[cx + u] - above[cx + u];
      }
      m01 += v * row_diff;
    }
    kp.angle = cv::fastAtan2(static_cast<float>(m01), static_cast<float>(m10));
  }
}

// Rotated BRIEF (OpenCV's ORB: 7x7 Gaussian blur, sigma 2, learned 256-pair pattern) for
// keypoints given in the level image's coordinates.
cv::Mat ComputeDescriptors(const cv::Mat& image, const std::vector<cv::KeyPoint>& keypoints) {
  if (keypoints.empty()) return cv::Mat(0, 32, CV_8U);
  // One pyramid level, keypoints at its octave 0; a small edge threshold so that OpenCV drops
  // none of them (they are kEdge px inside the image).
  cv::Ptr<cv::ORB> orb = cv::ORB::create(500, 1.2f, 1, kEdge - 3, 0, 2, cv::ORB::FAST_SCORE, kPatchSize);
  std::vector<cv::KeyPoint> level_keypoints = keypoints;
  for (cv::KeyPoint& kp : level_keypoints) kp.octave = 0;
  cv::Mat descriptors;
  orb->compute(image, level_keypoints, descriptors);
  if (level_keypoints.size() != keypoints.size() || descriptors.rows != static_cast<int>(keypoints.size()))
    throw Error("OrbExtractor: OpenCV dropped keypoints while computing descriptors");
  return descriptors;
}

}  // namespace

OrbExtractor::OrbExtractor(const OrbOptions& options) : options_(options) {
  options_.Check();
  const int levels = options_.num_levels;
  scale_factors_.resize(levels);
  inv_scale_factors_.resize(levels);
  level_sigma2_.resize(levels);
  inv_level_sigma2_.resize(levels);
  for (int l = 0; l < levels; ++l) {
    scale_factors_[l] = std::pow(options_.scale_factor, l);
    inv_scale_factors_[l] = 1.0 / scale_factors_[l];
    level_sigma2_[l] = scale_factors_[l] * scale_factors_[l];
    inv_level_sigma2_[l] = 1.0 / level_sigma2_[l];
  }
  features_per_level_ = FeaturesPerLevel(options_.num_features, options_.scale_factor, levels);
}

void OrbExtractor::Extract(const cv::Mat& gray, const cv::Mat& mask, std::vector<cv::KeyPoint>* keypoints,
                           cv::Mat* descriptors) const {
  if (keypoints == nullptr || descriptors == nullptr) throw Error("OrbExtractor: null output");
  if (gray.empty() || gray.type() != CV_8UC1) throw Error("OrbExtractor: expected a non-empty CV_8UC1 image");
  if (!mask.empty() && (mask.type() != CV_8UC1 || mask.size() != gray.size()))
    throw Error("OrbExtractor: the mask must be CV_8UC1 with the image's size");
  const int levels = num_levels();
  const std::vector<cv::Mat> pyramid = BuildPyramid(gray, scale_factors_);

  std::vector<std::vector<cv::KeyPoint>> corners(levels);
  std::vector<int> available(levels, 0);
  for (int l = 0; l < levels; ++l) {
    if (pyramid[l].empty()) continue;
    corners[l] = DetectCorners(pyramid[l], mask, scale_factors_[l], options_);
    available[l] = static_cast<int>(corners[l].size());
  }
  const std::vector<int> budgets = AllocateBudgets(features_per_level_, available);

  keypoints->clear();
  std::vector<cv::Mat> level_descriptors;
  for (int l = 0; l < levels; ++l) {
    if (budgets[l] == 0) continue;
    std::vector<cv::KeyPoint> selected;
    for (const int i : DistributeQuadtree(corners[l], DetectionArea(pyramid[l]), budgets[l]))
      selected.push_back(corners[l][i]);
    ComputeOrientations(pyramid[l], &selected);
    level_descriptors.push_back(ComputeDescriptors(pyramid[l], selected));
    const float scale = static_cast<float>(scale_factors_[l]);
    for (cv::KeyPoint& kp : selected) {
      kp.pt *= scale;
      kp.octave = l;
      kp.size = kPatchSize * scale;
      keypoints->push_back(kp);
    }
  }
  if (level_descriptors.empty())
    *descriptors = cv::Mat(0, 32, CV_8U);
  else
    cv::vconcat(level_descriptors, *descriptors);
}

}  // namespace esdslam
