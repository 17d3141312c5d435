#pragma once
// Boundary refinement of person masks by depth region growing (ESD-SLAM, Algorithm 1).
//
// Segmentation masks are coarse at object boundaries: they bleed onto the background and miss
// thin parts. For every connected component of the network mask we take seed pixels inside it
// (the mask eroded, with valid depth, split into depth layers; small layers are background) and
// grow a region from the largest layer, and from other layers that stay mostly inside the mask,
// over 4- (or 8-) neighbours (explicit stack) while the depth step between neighbours stays below a
// depth-dependent tolerance, within the network mask dilated by a band of growth_band_px. The
// result follows the person's depth silhouette. Mask pixels without valid depth cannot be
// decided by depth: they are kept and dilated a little.
//
// Depth tolerance between 8-neighbours p -> q (metres):
//     |z_q - z_p| <= abs_tolerance_m + depth_sq_tolerance * z_p^2
// The z^2 term follows the structured-light depth noise (sigma ~ 1.5e-3 z^2 for Kinect) and
// the depth step of a slanted surface between neighbouring pixels (~ z / f * tan(angle)).
// A person stands >= 0.2 m in front of the background, well above the tolerance up to ~4 m.
// In addition, a grown pixel must stay within max_depth_from_seed_m of its layer's median depth,
// which, with the band, limits leaks into the floor at the feet (depth is continuous there).

#include <vector>

#include <string>

#include <opencv2/core.hpp>

namespace esdslam {

struct RegionGrowingOptions {
  double abs_tolerance_m = 0.03;      // constant part of the neighbour tolerance
  double depth_sq_tolerance = 0.01;   // 1/m: depth-squared part of the neighbour tolerance
  double max_depth_from_seed_m = 0.8; // grown pixels stay within this of the seeds' median depth
  double seed_split_gap_m = 0.1;      // seed depths separated by a larger gap are different layers
  double min_seed_fraction = 0.05;    // seed layers with fewer seeds (fraction) are background
  // Besides the largest seed layer, a layer is kept only if at most this fraction of its grown
  // region lies outside the network mask (background seen around the person spreads out).
  double max_outside_fraction = 0.5;
  // Seeds come from the centre region: the component eroded by
  // max(seed_erosion_px, seed_core_fraction * min(box width, box height)).
  int seed_erosion_px = 4;
  double seed_core_fraction = 0.1;
  int connectivity = 4;               // growth neighbourhood: 4 or 8
  int growth_band_px = 16;            // growth stays within the network mask dilated by this
  int no_depth_dilation_px = 2;       // dilation of kept mask pixels that have no valid depth
  int min_component_px = 30;          // smaller mask components are dropped (noise)

  // Throws esdslam::Error on negative or inconsistent values.
  // Throws SettingError naming the key under `key_prefix` (the settings binding's prefix).
  void Check(const std::string& key_prefix = "Dynamic.grow.") const;
};

// raw_mask: CV_8U, nonzero = person (network output). depth_m: CV_32F metres, 0 = invalid, same
// size. Returns CV_8U, 255 = dynamic. Throws Error on a type or size mismatch.
cv::Mat RefineDynamicMask(const cv::Mat& raw_mask, const cv::Mat& depth_m, const RegionGrowingOptions& options);

// The growth step on its own, shared with the geometry check: grows from `seeds` (pixels with
// valid depth) inside `box` (and where `allowed`, CV_8U, is nonzero, unless it is empty) with
// the neighbour tolerance above, keeping pixels within max_depth_from_seed_m of
// `reference_depth_m`. Sets grown pixels of `region` (CV_8U, image size) to 255; pixels already
// 255 are not revisited. Returns the number of pixels added.
int GrowDepthRegion(const cv::Mat& depth_m, const std::vector<cv::Point>& seeds, const cv::Rect& box,
                    double reference_depth_m, const RegionGrowingOptions& options, cv::Mat& region,
                    const cv::Mat& allowed = cv::Mat());

}  // namespace esdslam
