#pragma once
// The geometry check's dynamic mask, grown from its flags (current pixels where something now
// covers what the reference keyframes saw).
//
// 1. Clusters: flags within cluster_radius_px of each other. A cluster is kept if it has at least
//    min_cluster_points flags and its support, covered / (covered + consistent) over the tested
//    points within cluster_radius_px / 2 of its flags, is at least min_cluster_support: a mover
//    covers what was behind it over an area, while a misregistered static depth edge (pose error,
//    colour/depth timing) yields a thin line of flags amid consistent points.
// 2. Growth (dynamic/region_growing.h GrowDepthRegion, depth-continuous neighbours) from the
//    cluster's flags. Flags mark only the part of a mover that now covers what the keyframes saw
//    (its leading side), so the growth must reach across the object: it stays within
//    mask_radius_m (an object-size prior: about a person's width) of the flags, i.e.
//    fx * mask_radius_m / z pixels at the cluster's median depth z (at most max_mask_radius_px),
//    which also limits leaks into the floor at the feet, where depth is continuous. (Points
//    tested consistent cannot stop the growth: on a mover not yet detected, the keyframes' own
//    points on it are consistent with its body when it moves sideways.)

#include <vector>

#include <opencv2/core.hpp>

#include "camera/pinhole_camera.h"
#include "dynamic/geometry_check.h"

namespace esdslam {

// depth_m: current CV_32F depth; static_pixels: pixels of points tested consistent. Returns
// CV_8U, 255 = dynamic.
cv::Mat MaskFromFlags(const PinholeCamera& camera, const cv::Mat& depth_m, const std::vector<FlaggedPoint>& flags,
                      const std::vector<cv::Point>& static_pixels, const GeometryCheckOptions& options);

}  // namespace esdslam
