#pragma once
// Statistical outlier removal: for every point the mean distance to its k nearest neighbours
// (searched within a radius of `search_radius`); points whose mean distance exceeds
// mean + std_ratio * std over the cloud, or that have fewer than k neighbours in the radius,
// are removed. Same statistic as PCL's StatisticalOutlierRemoval, with a bounded search radius.

#include "dense/point_cloud.h"

namespace esdslam {

struct OutlierFilterOptions {
  int neighbors = 8;
  double std_ratio = 2.0;
  double search_radius = 0.05;  // m
};

PointCloud RemoveStatisticalOutliers(const PointCloud& cloud, const OutlierFilterOptions& options);

}  // namespace esdslam
