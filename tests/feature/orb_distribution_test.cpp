#include "feature/orb_distribution.h"

#include <numeric>
#include <random>
#include <set>

#include <gtest/gtest.h>

namespace esdslam {
namespace {

TEST(FeaturesPerLevel, GeometricSeriesSummingToTheBudget) {
  const std::vector<int> per_level = FeaturesPerLevel(1000, 1.2, 8);
  ASSERT_EQ(per_level.size(), 8u);
  EXPECT_EQ(std::accumulate(per_level.begin(), per_level.end(), 0), 1000);
  // ORB-SLAM2's numbers for 1000 / 1.2 / 8: first level 217, ratio 1/1.2.
  EXPECT_EQ(per_level[0], 217);
  for (int l = 1; l < 7; ++l) EXPECT_NEAR(per_level[l], per_level[l - 1] / 1.2, 1.0);
  EXPECT_EQ(FeaturesPerLevel(500, 1.2, 1), std::vector<int>{500});
}

TEST(AllocateBudgets, KeepsDesiredWhenEnoughCorners) {
  EXPECT_EQ(AllocateBudgets({10, 8, 6}, {100, 100, 100}), (std::vector<int>{10, 8, 6}));
}

TEST(AllocateBudgets, MovesTheDeficitToLevelsWithSpareCorners) {
  const std::vector<int> budget = AllocateBudgets({100, 80, 60, 50}, {500, 20, 70, 0});
  EXPECT_EQ(std::accumulate(budget.begin(), budget.end(), 0), 290);
  EXPECT_EQ(budget[1], 20);
  EXPECT_EQ(budget[3], 0);
  EXPECT_LE(budget[2], 70);
  EXPECT_GE(budget[0], 100);
}

TEST(AllocateBudgets, CapsAtAvailableCorners) {
  const std::vector<int> budget = AllocateBudgets({100, 80}, {30, 20});
  EXPECT_EQ(budget, (std::vector<int>{30, 20}));
}

std::vector<cv::KeyPoint> RandomCorners(int count, const cv::Rect2f& area, std::mt19937* rng) {
  std::uniform_real_distribution<float> x(area.x, area.x + area.width), y(area.y, area.y + area.height);
  std::uniform_real_distribution<float> response(10, 100);
  std::vector<cv::KeyPoint> corners;
  for (int i = 0; i < count; ++i) corners.emplace_back(cv::Point2f(x(*rng), y(*rng)), 7.f, -1, response(*rng));
  return corners;
}

TEST(DistributeQuadtree, SpreadsKeypointsOverSparseAndDenseRegions) {
  std::mt19937 rng(5);
  const cv::Rect2f area(0, 0, 640, 480);
  // A dense cluster (2000 strong corners in a 100x100 box) and 200 weak corners everywhere.
  std::vector<cv::KeyPoint> corners = RandomCorners(2000, cv::Rect2f(0, 0, 100, 100), &rng);
  for (auto& c : corners) c.response += 200;
  for (const auto& c : RandomCorners(200, area, &rng)) corners.push_back(c);
  const std::vector<int> kept = DistributeQuadtree(corners, area, 300);
  EXPECT_LE(kept.size(), 300u);
  EXPECT_GE(kept.size(), 290u);
  EXPECT_EQ(std::set<int>(kept.begin(), kept.end()).size(), kept.size());
  int in_cluster = 0;
  for (int i : kept) in_cluster += corners[i].pt.x < 100 && corners[i].pt.y < 100;
  // Keeping the strongest would take all 300 from the cluster (3% of the area); the quadtree
  // keeps a minority there and most (~190 in total) of the sparse corners.
  EXPECT_LT(in_cluster, 140);
  EXPECT_GT(static_cast<int>(kept.size()) - in_cluster, 160);
}

TEST(DistributeQuadtree, KeepsTheStrongestCornerOfEachNodeAndAllWhenBudgetIsLarge) {
  std::mt19937 rng(9);
  const cv::Rect2f area(19, 19, 600, 440);
  const std::vector<cv::KeyPoint> corners = RandomCorners(50, area, &rng);
  std::vector<int> all = DistributeQuadtree(corners, area, 1000);
  std::vector<int> expected(50);
  std::iota(expected.begin(), expected.end(), 0);
  EXPECT_EQ(all, expected);
  // Two corners close together with a budget of one: the stronger one wins.
  const std::vector<cv::KeyPoint> pair = {cv::KeyPoint(100, 100, 7, -1, 20), cv::KeyPoint(101, 100, 7, -1, 50)};
  EXPECT_EQ(DistributeQuadtree(pair, area, 1), std::vector<int>{1});
  // Corners outside the area are ignored.
  const std::vector<cv::KeyPoint> outside = {cv::KeyPoint(5, 5, 7, -1, 99), cv::KeyPoint(100, 100, 7, -1, 1)};
  EXPECT_EQ(DistributeQuadtree(outside, area, 10), std::vector<int>{1});
  EXPECT_TRUE(DistributeQuadtree(corners, area, 0).empty());
}

}  // namespace
}  // namespace esdslam
