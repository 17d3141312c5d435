#include "dynamic/flag_mask.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "dynamic/region_growing.h"

namespace esdslam {
namespace {

struct Cluster {
  std::vector<cv::Point> seeds;
  std::vector<float> depths;
  int consistent = 0;  // tested-consistent points within its discs
  cv::Rect box;        // bounding box of its discs (image pixels)
  float median_depth_m = 0;
  int radius_px = 0;   // 0: rejected
};

// Growth radius (px) around the flags of a cluster at median depth z.
int MaskRadiusPx(const PinholeCamera& camera, double z, const GeometryCheckOptions& options) {
  const double radius = camera.fx() * options.mask_radius_m / std::max(z, options.min_depth_m);
  return std::clamp(static_cast<int>(std::lround(radius)), options.cluster_radius_px, options.max_mask_radius_px);
}

// Flags whose discs (radius cluster_radius_px / 2) touch form a cluster; found on a grid of
// kCell x kCell pixel cells (flags and discs rasterised to cells: cell accuracy suffices for a
// grouping radius of tens of pixels, and it is 16x fewer pixels to draw and label) over the
// flags' bounding box only (flags are usually few and local). Counts the consistent points per
// cluster.
constexpr int kCell = 4;
std::vector<Cluster> FindClusters(const cv::Size& size, const std::vector<FlaggedPoint>& flags,
                                  const std::vector<cv::Point>& static_pixels, const GeometryCheckOptions& options) {
  const int disc = options.cluster_radius_px / 2;
  const int disc_cells = std::max(1, (disc + kCell / 2) / kCell);
  const auto cell = [](const cv::Point& p) { return cv::Point(p.x / kCell, p.y / kCell); };
  const cv::Size cells((size.width + kCell - 1) / kCell, (size.height + kCell - 1) / kCell);
  cv::Rect roi(cell(flags[0].pixel), cv::Size(1, 1));
  for (const auto& flag : flags) roi |= cv::Rect(cell(flag.pixel), cv::Size(1, 1));
  roi = cv::Rect(roi.x - disc_cells, roi.y - disc_cells, roi.width + 2 * disc_cells, roi.height + 2 * disc_cells) &
        cv::Rect(cv::Point(), cells);
  cv::Mat discs = cv::Mat::zeros(roi.size(), CV_8U);
  for (const auto& flag : flags) cv::circle(discs, cell(flag.pixel) - roi.tl(), disc_cells, 255, cv::FILLED);
  cv::Mat labels, stats, centroids;
  const int num_labels = cv::connectedComponentsWithStats(discs, labels, stats, centroids, 8, CV_32S);
  std::vector<Cluster> clusters(num_labels);
  for (const auto& flag : flags) {
    Cluster& cluster = clusters[labels.at<int>(cell(flag.pixel) - roi.tl())];
    cluster.seeds.push_back(flag.pixel);
    cluster.depths.push_back(static_cast<float>(flag.measured_depth_m));
  }
  for (const cv::Point& pixel : static_pixels) {
    const cv::Point c = cell(pixel);
    if (roi.contains(c)) ++clusters[labels.at<int>(c - roi.tl())].consistent;
  }
  const cv::Rect image(cv::Point(), size);
  for (int label = 1; label < num_labels; ++label)
    clusters[label].box = cv::Rect((stats.at<int>(label, cv::CC_STAT_LEFT) + roi.x) * kCell,
                                   (stats.at<int>(label, cv::CC_STAT_TOP) + roi.y) * kCell,
                                   stats.at<int>(label, cv::CC_STAT_WIDTH) * kCell,
                                   stats.at<int>(label, cv::CC_STAT_HEIGHT) * kCell) & image;
  clusters.erase(clusters.begin());  // label 0: outside every disc
  return clusters;
}

bool Supported(const Cluster& cluster, const GeometryCheckOptions& options) {
  const int covered = static_cast<int>(cluster.seeds.size());
  return covered >= options.min_cluster_points &&
         covered >= options.min_cluster_support * static_cast<double>(covered + cluster.consistent);
}

// Where growth may go: within each cluster's radius of the supported flags, from a distance
// transform at 1/kCell resolution (a loose bound: cell accuracy suffices, and the cost does not
// grow with the number of flags).
cv::Mat AllowedArea(const cv::Size& size, const std::vector<Cluster>& clusters) {
  const cv::Size cells((size.width + kCell - 1) / kCell, (size.height + kCell - 1) / kCell);
  cv::Mat not_flag(cells, CV_8U, cv::Scalar(255));
  for (const Cluster& cluster : clusters) {
    if (cluster.radius_px == 0) continue;
    for (const auto& seed : cluster.seeds) not_flag.at<std::uint8_t>(seed.y / kCell, seed.x / kCell) = 0;
  }
  cv::Mat distance;  // to the nearest flag cell, in cells
  cv::distanceTransform(not_flag, distance, cv::DIST_L2, cv::DIST_MASK_3);
  cv::Mat allowed_cells = cv::Mat::zeros(cells, CV_8U);
  for (const Cluster& cluster : clusters) {
    if (cluster.radius_px == 0) continue;
    const int r = cluster.radius_px;
    const cv::Rect box =
        cv::Rect((cluster.box.x - r) / kCell, (cluster.box.y - r) / kCell, (cluster.box.width + 2 * r) / kCell + 2,
                 (cluster.box.height + 2 * r) / kCell + 2) & cv::Rect(cv::Point(), cells);
    allowed_cells(box).setTo(255, distance(box) <= static_cast<float>(r) / kCell);
  }
  cv::Mat allowed;
  cv::resize(allowed_cells, allowed, cv::Size(), kCell, kCell, cv::INTER_NEAREST);
  return allowed(cv::Rect(cv::Point(), size)).clone();  // continuous, image size
}

}  // namespace

cv::Mat MaskFromFlags(const PinholeCamera& camera, const cv::Mat& depth_m, const std::vector<FlaggedPoint>& flags,
                      const std::vector<cv::Point>& static_pixels, const GeometryCheckOptions& options) {
  cv::Mat mask = cv::Mat::zeros(depth_m.size(), CV_8U);
  if (static_cast<int>(flags.size()) < options.min_cluster_points) return mask;
  std::vector<Cluster> clusters = FindClusters(depth_m.size(), flags, static_pixels, options);
  bool any = false;
  for (Cluster& cluster : clusters) {
    if (!Supported(cluster, options)) continue;
    auto& d = cluster.depths;
    std::nth_element(d.begin(), d.begin() + d.size() / 2, d.end());
    cluster.median_depth_m = d[d.size() / 2];
    cluster.radius_px = MaskRadiusPx(camera, cluster.median_depth_m, options);
    any = true;
  }
  if (!any) return mask;
  const cv::Mat allowed = AllowedArea(depth_m.size(), clusters);
  const cv::Rect image(0, 0, depth_m.cols, depth_m.rows);
  for (const Cluster& cluster : clusters) {
    if (cluster.radius_px == 0) continue;
    const int r = cluster.radius_px;
    const cv::Rect box =
        cv::Rect(cluster.box.x - r, cluster.box.y - r, cluster.box.width + 2 * r, cluster.box.height + 2 * r) & image;
    GrowDepthRegion(depth_m, cluster.seeds, box, cluster.median_depth_m, options.growing, mask, allowed);
  }
  return mask;
}

}  // namespace esdslam
