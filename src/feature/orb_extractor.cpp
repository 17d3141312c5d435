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

// FAST corners of one level inside the detection area and the mask. A single FAST pass at the
// minimum threshold (with non-maximum suppression) gives, per cell, exactly the corners FAST at
// the initial threshold would give (those scoring >= it) plus the fallback set; each ~30 px cell
// keeps the initial-threshold corners, or all its corners when it has none of those.
std::vector<cv::KeyPoint> DetectCorners(const cv::Mat& image, const cv::Mat& mask, double scale,
                                        const OrbOptions& options) {
  const cv::Rect2f area = DetectionArea(image);
  if (area.empty()) return {};
  std::vector<cv::KeyPoint> fast;
  cv::FAST(image, fast, options.min_fast_threshold, true);
  const int cols = std::max(1, static_cast<int>(area.width / kCellSize));
  const int rows = std::max(1, static_cast<int>(area.height / kCellSize));
  const float cell_width = area.width / cols, cell_height = area.height / rows;
  std::vector<int> cell_of(fast.size(), -1);
  std::vector<char> cell_has_strong(static_cast<size_t>(cols) * rows, 0);
  for (size_t i = 0; i < fast.size(); ++i) {
    const cv::Point2f& p = fast[i].pt;
    if (!area.contains(p) || !AllowedByMask(mask, p, scale)) continue;
    const int col = std::min(cols - 1, static_cast<int>((p.x - area.x) / cell_width));
    const int row = std::min(rows - 1, static_cast<int>((p.y - area.y) / cell_height));
    cell_of[i] = row * cols + col;
    if (fast[i].response >= options.initial_fast_threshold) cell_has_strong[cell_of[i]] = 1;
  }
  std::vector<cv::KeyPoint> corners;
  corners.reserve(fast.size());
  for (size_t i = 0; i < fast.size(); ++i) {
    if (cell_of[i] < 0) continue;
    if (cell_has_strong[cell_of[i]] && fast[i].response < options.initial_fast_threshold) continue;
    corners.push_back(fast[i]);
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
