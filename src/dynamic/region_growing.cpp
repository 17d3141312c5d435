#include "dynamic/region_growing.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "common/error.h"
#include "common/setting_error.h"
#include "dynamic/mask_dilation.h"

namespace esdslam {
namespace {


struct SeedGroup {
  std::vector<cv::Point> seeds;
  double median_depth_m = 0;
};

constexpr int kCoarse = 4;  // components and seed grid are computed at 1/kCoarse resolution

// Seed candidates of coarse component `label` (coarse_box in coarse pixels): its centre region
// (the component eroded by a radius that grows with its size, square kernel; the whole
// component if erosion leaves nothing), one full-resolution pixel per coarse pixel (its centre)
// where the network mask is set and depth is valid, as (depth, pixel) sorted by depth.
std::vector<std::pair<float, cv::Point>> CoreSeeds(const cv::Mat& coarse_labels, int label, const cv::Rect& coarse_box,
                                                  const cv::Mat& raw_mask, const cv::Mat& depth_m,
                                                  const RegionGrowingOptions& options) {
  const cv::Mat component = coarse_labels(coarse_box) == label;
  const int radius_px = std::max(options.seed_erosion_px, static_cast<int>(options.seed_core_fraction * kCoarse *
                                                                            std::min(coarse_box.width, coarse_box.height)));
  const int radius = (radius_px + kCoarse - 1) / kCoarse;
  cv::Mat core;
  cv::erode(component, core, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * radius + 1, 2 * radius + 1)));
  if (cv::countNonZero(core) == 0) core = component;
  std::vector<std::pair<float, cv::Point>> candidates;
  for (int y = 0; y < coarse_box.height; ++y) {
    const uchar* core_row = core.ptr<uchar>(y);
    const int v = std::min(depth_m.rows - 1, (coarse_box.y + y) * kCoarse + kCoarse / 2);
    const float* depth_row = depth_m.ptr<float>(v);
    const uchar* raw_row = raw_mask.ptr<uchar>(v);
    for (int x = 0; x < coarse_box.width; ++x) {
      const int u = std::min(depth_m.cols - 1, (coarse_box.x + x) * kCoarse + kCoarse / 2);
      if (core_row[x] && raw_row[u] && depth_row[u] > 0) candidates.emplace_back(depth_row[u], cv::Point(u, v));
    }
  }
  std::sort(candidates.begin(), candidates.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  return candidates;
}

// Splits sorted seed candidates into depth layers at gaps > seed_split_gap_m (two people
// overlapping in the image are two layers) and drops layers holding less than
// min_seed_fraction of the seeds (background seen through the mask). Largest layer first.
std::vector<SeedGroup> SeedLayers(const std::vector<std::pair<float, cv::Point>>& candidates,
                                  const RegionGrowingOptions& options) {
  std::vector<SeedGroup> groups;
  std::size_t begin = 0;
  for (std::size_t i = 1; i <= candidates.size(); ++i) {
    if (i < candidates.size() && candidates[i].first - candidates[i - 1].first <= options.seed_split_gap_m) continue;
    if (static_cast<double>(i - begin) >= options.min_seed_fraction * static_cast<double>(candidates.size())) {
      SeedGroup group;
      group.median_depth_m = candidates[(begin + i) / 2].first;
      for (std::size_t j = begin; j < i; ++j) {  // seeds far from the layer's bulk are not trusted
        if (std::abs(candidates[j].first - group.median_depth_m) <= options.max_depth_from_seed_m)
          group.seeds.push_back(candidates[j].second);
      }
      groups.push_back(std::move(group));
    }
    begin = i;
  }
  std::stable_sort(groups.begin(), groups.end(),
                   [](const SeedGroup& a, const SeedGroup& b) { return a.seeds.size() > b.seeds.size(); });
  return groups;
}

// Grows the largest layer, then every other layer whose region stays mostly inside the network
// mask (background around the person spreads over the whole band, a second person does not).
void GrowSeedLayers(const cv::Mat& depth_m, const cv::Mat& raw_mask, const std::vector<SeedGroup>& groups,
                    const cv::Rect& box, const cv::Mat& allowed, const RegionGrowingOptions& options, cv::Mat& refined) {
  GrowDepthRegion(depth_m, groups[0].seeds, box, groups[0].median_depth_m, options, refined, allowed);
  for (std::size_t g = 1; g < groups.size(); ++g) {
    cv::Mat layer = cv::Mat::zeros(depth_m.size(), CV_8U);
    const int grown = GrowDepthRegion(depth_m, groups[g].seeds, box, groups[g].median_depth_m, options, layer, allowed);
    const int outside = cv::countNonZero(layer(box) & (raw_mask(box) == 0));
    if (grown > 0 && outside <= options.max_outside_fraction * grown) refined(box).setTo(255, layer(box));
  }
}

// Mask pixels without valid depth, dilated: depth cannot decide them, so they stay dynamic.
cv::Mat NoDepthPart(const cv::Mat& raw_mask, const cv::Mat& depth_m, int dilation_px) {
  cv::Mat no_depth = (raw_mask != 0) & (depth_m <= 0);
  if (dilation_px > 0 && cv::countNonZero(no_depth) > 0) no_depth = DilateEllipse(no_depth, dilation_px);
  return no_depth;
}

// The network mask dilated by about band_px, computed on the coarse mask (kCoarse x kCoarse
// cells; square kernel) and enlarged to `size`: a loose bound, so cell accuracy suffices.
cv::Mat GrowthBand(const cv::Mat& coarse_mask, const cv::Size& size, int band_px) {
  const int cells = (band_px + kCoarse - 1) / kCoarse;
  cv::Mat dilated, band;
  cv::dilate(coarse_mask, dilated, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * cells + 1, 2 * cells + 1)));
  cv::resize(dilated, band, cv::Size(), kCoarse, kCoarse, cv::INTER_NEAREST);
  return band(cv::Rect(0, 0, size.width, size.height)).clone();  // continuous, image size
}

}  // namespace

void RegionGrowingOptions::Check(const std::string& key_prefix) const {
  const std::string& k = key_prefix;
  CheckRange(k + "absTolerance", abs_tolerance_m, 1e-4, 2.0, "m");
  CheckRange(k + "depthSqTolerance", depth_sq_tolerance, 0.0, 1.0, "1/m");
  CheckRange(k + "maxDepthFromSeed", max_depth_from_seed_m, 0.01, 10.0, "m");
  CheckRange(k + "seedSplitGap", seed_split_gap_m, 0.001, 10.0, "m");
  CheckRange(k + "minSeedFraction", min_seed_fraction, 0.0, 0.999);
  CheckRange(k + "maxOutsideFraction", max_outside_fraction, 0.0, 1.0);
  CheckRange(k + "seedErosion", seed_erosion_px, 0, 100, "px");
  CheckRange(k + "seedCoreFraction", seed_core_fraction, 0.0, 0.499);
  CheckSetting(connectivity == 4 || connectivity == 8, k + "connectivity", "must be 4 or 8");
  CheckRange(k + "growthBand", growth_band_px, 0, 500, "px");
  CheckRange(k + "noDepthDilation", no_depth_dilation_px, 0, 100, "px");
  CheckRange(k + "minComponent", min_component_px, 0, 1000000, "px");
}

namespace {

// The growth's state: images, bounds ([x0, x1) x [y0, y1)) and thresholds.
struct Growth {
  const float* depth;
  uchar* mark;
  const uchar* allow;  // null: everywhere
  int cols, x0, x1, y0, y1;
  float reference, max_from_reference, abs_tolerance, sq_tolerance;

  // Whether pixel i joins the region from a region neighbour of depth z_from.
  bool Joinable(int i, float z_from) const {
    const float z = depth[i];
    if (mark[i] || (allow != nullptr && !allow[i]) || !(z > 0)) return false;
    return std::abs(z - z_from) <= abs_tolerance + sq_tolerance * z_from * z_from &&
           std::abs(z - reference) <= max_from_reference;
  }
};

// 8-connectivity: pixel by pixel from an explicit stack.
int GrowPixels(const Growth& g, std::vector<cv::Point>& stack) {
  static const int kNeighbours[8][2] = {{-1, -1}, {1, -1}, {-1, 1}, {1, 1}, {0, -1}, {0, 1}, {-1, 0}, {1, 0}};
  int added = 0;
  while (!stack.empty()) {
    const cv::Point p = stack.back();
    stack.pop_back();
    const float z = g.depth[p.y * g.cols + p.x];
    for (const auto& offset : kNeighbours) {
      const int x = p.x + offset[0], y = p.y + offset[1];
      if (x < g.x0 || x >= g.x1 || y < g.y0 || y >= g.y1 || !g.Joinable(y * g.cols + x, z)) continue;
      g.mark[y * g.cols + x] = 255;
      ++added;
      stack.emplace_back(x, y);
    }
  }
  return added;
}

// 4-connectivity, scanline: the same region, found run by run along rows (memory order, a few
// times faster). A popped seed extends left and right; in the rows above and below, the first
// pixel of every run reachable from the span becomes a seed (the rest of the run is reached when
// that seed extends).
int GrowRuns(const Growth& g, std::vector<cv::Point>& stack) {
  int added = 0;
  while (!stack.empty()) {
    const cv::Point seed = stack.back();
    stack.pop_back();
    const int row = seed.y * g.cols;
    int left = seed.x, right = seed.x;
    for (; left - 1 >= g.x0 && g.Joinable(row + left - 1, g.depth[row + left]); --left) g.mark[row + left - 1] = 255;
    for (; right + 1 < g.x1 && g.Joinable(row + right + 1, g.depth[row + right]); ++right) g.mark[row + right + 1] = 255;
    added += right - left;
    for (const int y : {seed.y - 1, seed.y + 1}) {
      if (y < g.y0 || y >= g.y1) continue;
      const int next = y * g.cols;
      for (int x = left; x <= right; ++x) {
        if (!g.Joinable(next + x, g.depth[row + x])) continue;
        g.mark[next + x] = 255;
        ++added;
        stack.emplace_back(x, y);
        while (x + 1 <= right && g.Joinable(next + x + 1, g.depth[next + x])) ++x;  // same run
      }
    }
  }
  return added;
}

}  // namespace

int GrowDepthRegion(const cv::Mat& depth_m, const std::vector<cv::Point>& seeds, const cv::Rect& box,
                    double reference_depth_m, const RegionGrowingOptions& options, cv::Mat& region,
                    const cv::Mat& allowed) {
  CV_Assert(depth_m.type() == CV_32F && region.type() == CV_8U && region.size() == depth_m.size() &&
            depth_m.isContinuous() && region.isContinuous());
  const bool limited = !allowed.empty();
  CV_Assert(!limited || (allowed.type() == CV_8U && allowed.size() == depth_m.size() && allowed.isContinuous()));
  const cv::Rect inside = box & cv::Rect(0, 0, depth_m.cols, depth_m.rows);
  const Growth growth{depth_m.ptr<float>(), region.ptr<uchar>(), limited ? allowed.ptr<uchar>() : nullptr,
                      depth_m.cols, inside.x, inside.x + inside.width, inside.y, inside.y + inside.height,
                      static_cast<float>(reference_depth_m), static_cast<float>(options.max_depth_from_seed_m),
                      static_cast<float>(options.abs_tolerance_m), static_cast<float>(options.depth_sq_tolerance)};
  std::vector<cv::Point> stack;
  stack.reserve(1024);
  int added = 0;
  for (const cv::Point& seed : seeds) {
    const int i = seed.y * depth_m.cols + seed.x;
    if (!inside.contains(seed) || growth.mark[i] || !(growth.depth[i] > 0)) continue;
    growth.mark[i] = 255;
    ++added;
    stack.push_back(seed);
  }
  return added + (options.connectivity == 8 ? GrowPixels(growth, stack) : GrowRuns(growth, stack));
}

cv::Mat RefineDynamicMask(const cv::Mat& raw_mask, const cv::Mat& depth_m, const RegionGrowingOptions& options) {
  if (raw_mask.type() != CV_8U || depth_m.type() != CV_32F || raw_mask.size() != depth_m.size())
    throw Error("RefineDynamicMask: expected a CV_8U mask and a CV_32F depth image of the same size");
  cv::Mat refined = cv::Mat::zeros(raw_mask.size(), CV_8U);
  if (cv::countNonZero(raw_mask) == 0) return refined;
  // Components on a 1/kCoarse image where a coarse pixel is set if any of its pixels is.
  cv::Mat coarse, labels, stats, centroids;
  cv::resize(raw_mask != 0, coarse, cv::Size((raw_mask.cols + kCoarse - 1) / kCoarse, (raw_mask.rows + kCoarse - 1) / kCoarse),
             0, 0, cv::INTER_AREA);
  const int num_labels = cv::connectedComponentsWithStats(coarse > 0, labels, stats, centroids, 8, CV_32S);
  const int band = options.growth_band_px;
  const cv::Mat allowed = GrowthBand(coarse > 0, raw_mask.size(), band);
  const cv::Rect image(0, 0, raw_mask.cols, raw_mask.rows);
  cv::Rect mask_box;  // of all components
  for (int label = 1; label < num_labels; ++label) {
    if (stats.at<int>(label, cv::CC_STAT_AREA) * kCoarse * kCoarse < options.min_component_px) continue;
    const cv::Rect coarse_box(stats.at<int>(label, cv::CC_STAT_LEFT), stats.at<int>(label, cv::CC_STAT_TOP),
                              stats.at<int>(label, cv::CC_STAT_WIDTH), stats.at<int>(label, cv::CC_STAT_HEIGHT));
    const cv::Rect component_box =
        cv::Rect(coarse_box.x * kCoarse, coarse_box.y * kCoarse, coarse_box.width * kCoarse, coarse_box.height * kCoarse) &
        image;
    mask_box |= component_box;
    const std::vector<SeedGroup> groups =
        SeedLayers(CoreSeeds(labels, label, coarse_box, raw_mask, depth_m, options), options);
    if (groups.empty()) {  // no usable depth inside: keep the network's mask as it is
      refined(component_box).setTo(255, raw_mask(component_box) != 0);
      continue;
    }
    const cv::Rect box = cv::Rect(component_box.x - band, component_box.y - band, component_box.width + 2 * band,
                                  component_box.height + 2 * band) & image;
    GrowSeedLayers(depth_m, raw_mask, groups, box, allowed, options, refined);
  }
  const int margin = options.no_depth_dilation_px;
  mask_box = cv::Rect(mask_box.x - margin, mask_box.y - margin, mask_box.width + 2 * margin,
                      mask_box.height + 2 * margin) & image;
  if (!mask_box.empty()) refined(mask_box).setTo(255, NoDepthPart(raw_mask(mask_box), depth_m(mask_box), margin));
  return refined;
}

}  // namespace esdslam
