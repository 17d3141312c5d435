#include "feature/feature_grid.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "common/error.h"

namespace esdslam {
namespace {

std::vector<int> BruteForce(const std::vector<cv::Point2f>& points, const std::vector<int>& levels, double u,
                            double v, double radius, int min_level, int max_level) {
  std::vector<int> result;
  for (int i = 0; i < static_cast<int>(points.size()); ++i) {
    if (min_level >= 0 && levels[i] < min_level) continue;
    if (max_level >= 0 && levels[i] > max_level) continue;
    if (std::abs(points[i].x - u) < radius && std::abs(points[i].y - v) < radius) result.push_back(i);
  }
  return result;
}

TEST(FeatureGrid, EqualsBruteForceRadiusQuery) {
  std::mt19937 rng(42);
  // Undistorted bounds are not the image rectangle; some points fall outside them.
  const double min_u = -12.5, max_u = 651.0, min_v = -8.0, max_v = 489.5;
  std::uniform_real_distribution<float> u_dist(-40, 680), v_dist(-30, 510);
  std::uniform_int_distribution<int> level_dist(0, 7);
  std::vector<cv::Point2f> points;
  std::vector<int> levels;
  for (int i = 0; i < 1500; ++i) {
    points.emplace_back(u_dist(rng), v_dist(rng));
    levels.push_back(level_dist(rng));
  }
  // Exact duplicates and points on cell borders.
  points.push_back(points[5]);
  levels.push_back(levels[5]);
  points.emplace_back(static_cast<float>(min_u + (max_u - min_u) / 64 * 10), 100.f);
  levels.push_back(0);
  const FeatureGrid grid(points, levels, min_u, max_u, min_v, max_v);
  ASSERT_EQ(grid.size(), static_cast<int>(points.size()));

  std::uniform_real_distribution<double> radius_dist(0.5, 120);
  std::uniform_int_distribution<int> bound_dist(-1, 7);
  int nonempty = 0;
  for (int q = 0; q < 2000; ++q) {
    const double u = u_dist(rng), v = v_dist(rng), radius = radius_dist(rng);
    int min_level = bound_dist(rng), max_level = bound_dist(rng);
    if (q % 3 == 0) min_level = max_level = -1;
    const std::vector<int> expected = BruteForce(points, levels, u, v, radius, min_level, max_level);
    ASSERT_EQ(grid.FeaturesInArea(u, v, radius, min_level, max_level), expected) << "query " << q;
    nonempty += !expected.empty();
  }
  EXPECT_GT(nonempty, 1000);  // the check is not vacuous
  // A query centred exactly on a point.
  EXPECT_EQ(grid.FeaturesInArea(points[5].x, points[5].y, 0.01), BruteForce(points, levels, points[5].x,
                                                                             points[5].y, 0.01, -1, -1));
}

TEST(FeatureGrid, EmptyAndInvalid) {
  const FeatureGrid empty({}, {}, 0, 640, 0, 480);
  EXPECT_TRUE(empty.FeaturesInArea(320, 240, 1000).empty());
  EXPECT_THROW(FeatureGrid({cv::Point2f(1, 1)}, {}, 0, 640, 0, 480), Error);
  EXPECT_THROW(FeatureGrid({}, {}, 0, 0, 0, 480), Error);
  const FeatureGrid one({cv::Point2f(10, 10)}, {2}, 0, 640, 0, 480);
  EXPECT_TRUE(one.FeaturesInArea(10, 10, 0).empty());
  EXPECT_TRUE(one.FeaturesInArea(10, 10, 5, 3, -1).empty());
  EXPECT_EQ(one.FeaturesInArea(10, 10, 5, 2, 2), std::vector<int>{0});
}

}  // namespace
}  // namespace esdslam
