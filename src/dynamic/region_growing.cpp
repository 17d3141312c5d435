#include "dynamic/region_growing.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "common/error.h"

namespace esdslam {
namespace {

double NeighbourTolerance(double z, const RegionGrowingOptions& options) {
  return options.abs_tolerance_m + options.depth_sq_tolerance * z * z;
}

double Median(std::vector<float> values) {
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

cv::Rect GrowthBox(const cv::Rect& component_box, const cv::Size& image_size, const RegionGrowingOptions& options) {
  const int mx = options.box_margin_px + static_cast<int>(options.box_margin_fraction * component_box.width);
  const int my = options.box_margin_px + static_cast<int>(options.box_margin_fraction * component_box.height);
  const cv::Rect box(component_box.x - mx, component_box.y - my, component_box.width + 2 * mx,
                     component_box.height + 2 * my);
  return box & cv::Rect(0, 0, image_size.width, image_size.height);
}

// Seeds of component `label`: pixels of seed_source (the eroded mask, or the mask itself) with valid depth near the median depth.
std::vector<cv::Point> ComponentSeeds(const cv::Mat& labels, int label, const cv::Rect& box, const cv::Mat& seed_source,
                                      const cv::Mat& depth_m, const RegionGrowingOptions& options, double* median) {
  std::vector<cv::Point> candidates;
  std::vector<float> depths;
  for (int v = box.y; v < box.y + box.height; ++v) {
    const int* label_row = labels.ptr<int>(v);
    const uchar* source_row = seed_source.ptr<uchar>(v);
    const float* depth_row = depth_m.ptr<float>(v);
    for (int u = box.x; u < box.x + box.width; ++u) {
      if (label_row[u] != label || !source_row[u] || !(depth_row[u] > 0)) continue;
      candidates.emplace_back(u, v);
      depths.push_back(depth_row[u]);
    }
  }
  std::vector<cv::Point> seeds;
  if (candidates.empty()) return seeds;
  *median = Median(depths);
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    if (std::abs(depths[i] - *median) <= options.seed_depth_band_m) seeds.push_back(candidates[i]);
  }
  return seeds;
}

// Mask pixels without valid depth, dilated: depth cannot decide them, so they stay dynamic.
cv::Mat NoDepthPart(const cv::Mat& raw_mask, const cv::Mat& depth_m, int dilation_px) {
  cv::Mat no_depth = (raw_mask != 0) & (depth_m <= 0);
  if (dilation_px > 0 && cv::countNonZero(no_depth) > 0) {
    const cv::Mat kernel =
        cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * dilation_px + 1, 2 * dilation_px + 1));
    cv::dilate(no_depth, no_depth, kernel);
  }
  return no_depth;
}

}  // namespace

void RegionGrowingOptions::Check() const {
  if (!(abs_tolerance_m > 0) || !(depth_sq_tolerance >= 0))
    throw Error("region growing: abs_tolerance_m must be > 0 and depth_sq_tolerance >= 0");
  if (!(max_depth_from_seed_m > 0) || !(seed_depth_band_m > 0))
    throw Error("region growing: max_depth_from_seed_m and seed_depth_band_m must be > 0");
  if (seed_erosion_px < 0 || box_margin_px < 0 || no_depth_dilation_px < 0 || min_component_px < 0 ||
      !(box_margin_fraction >= 0))
    throw Error("region growing: pixel counts and margins must be >= 0");
}

int GrowDepthRegion(const cv::Mat& depth_m, const std::vector<cv::Point>& seeds, const cv::Rect& box,
                    double reference_depth_m, const RegionGrowingOptions& options, cv::Mat& region) {
  static const int kDu[8] = {-1, 0, 1, -1, 1, -1, 0, 1};
  static const int kDv[8] = {-1, -1, -1, 0, 0, 1, 1, 1};
  std::vector<cv::Point> stack;
  int added = 0;
  for (const cv::Point& seed : seeds) {
    if (!box.contains(seed) || region.at<uchar>(seed) || !(depth_m.at<float>(seed) > 0)) continue;
    region.at<uchar>(seed) = 255;
    ++added;
    stack.push_back(seed);
  }
  while (!stack.empty()) {
    const cv::Point p = stack.back();
    stack.pop_back();
    const float z = depth_m.at<float>(p);
    const double tolerance = NeighbourTolerance(z, options);
    for (int n = 0; n < 8; ++n) {
      const cv::Point q(p.x + kDu[n], p.y + kDv[n]);
      if (!box.contains(q)) continue;
      uchar& mark = region.at<uchar>(q);
      const float zq = depth_m.at<float>(q);
      if (mark || !(zq > 0) || std::abs(zq - z) > tolerance ||
          std::abs(zq - reference_depth_m) > options.max_depth_from_seed_m)
        continue;
      mark = 255;
      ++added;
      stack.push_back(q);
    }
  }
  return added;
}

cv::Mat RefineDynamicMask(const cv::Mat& raw_mask, const cv::Mat& depth_m, const RegionGrowingOptions& options) {
  if (raw_mask.type() != CV_8U || depth_m.type() != CV_32F || raw_mask.size() != depth_m.size())
    throw Error("RefineDynamicMask: expected a CV_8U mask and a CV_32F depth image of the same size");
  cv::Mat refined = cv::Mat::zeros(raw_mask.size(), CV_8U);
  if (cv::countNonZero(raw_mask) == 0) return refined;
  cv::Mat labels, stats, centroids;
  const int num_labels = cv::connectedComponentsWithStats(raw_mask != 0, labels, stats, centroids, 8, CV_32S);
  cv::Mat eroded;
  const int r = options.seed_erosion_px;
  cv::erode(raw_mask != 0, eroded, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * r + 1, 2 * r + 1)));
  for (int label = 1; label < num_labels; ++label) {
    if (stats.at<int>(label, cv::CC_STAT_AREA) < options.min_component_px) continue;
    const cv::Rect component_box(stats.at<int>(label, cv::CC_STAT_LEFT), stats.at<int>(label, cv::CC_STAT_TOP),
                                 stats.at<int>(label, cv::CC_STAT_WIDTH), stats.at<int>(label, cv::CC_STAT_HEIGHT));
    double median = 0;
    std::vector<cv::Point> seeds = ComponentSeeds(labels, label, component_box, eroded, depth_m, options, &median);
    if (seeds.empty()) seeds = ComponentSeeds(labels, label, component_box, raw_mask, depth_m, options, &median);
    if (seeds.empty()) {  // no usable depth inside: keep the network's component as it is
      refined.setTo(255, labels == label);
      continue;
    }
    GrowDepthRegion(depth_m, seeds, GrowthBox(component_box, raw_mask.size(), options), median, options, refined);
  }
  refined.setTo(255, NoDepthPart(raw_mask, depth_m, options.no_depth_dilation_px));
  return refined;
}

}  // namespace esdslam
