#pragma once
// Building blocks of OrbExtractor that do not touch pixels: how the keypoint budget is split
// over pyramid levels and how corners are thinned to an even spatial distribution.

#include <vector>

#include <opencv2/core.hpp>

namespace esdslam {

// ORB-SLAM2's per-level budget: a geometric series with ratio 1 / scale_factor summing to
// num_features (the last level takes the remainder).
std::vector<int> FeaturesPerLevel(int num_features, double scale_factor, int num_levels);

// Caps each level's desired budget at the corners it has and hands what is left over to the
// levels that still have spare corners (in proportion to their desired budget), so the total
// stays num_features = sum(desired) whenever enough corners exist anywhere. Deterministic.
std::vector<int> AllocateBudgets(const std::vector<int>& desired, const std::vector<int>& available);

// Quadtree distribution (ORB-SLAM2's DistributeOctTree): splits `area` into nodes until there
// are at least `budget` non-empty nodes or no node holds more than one corner, then keeps the
// strongest corner (highest response) of each node. Returns at most `budget` corner indices;
// when there are more nodes than the budget the weakest winners are dropped.
// Corners outside `area` are ignored.
std::vector<int> DistributeQuadtree(const std::vector<cv::KeyPoint>& corners, const cv::Rect2f& area,
                                    int budget);

}  // namespace esdslam
