#include "feature/orb_distribution.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace esdslam {

std::vector<int> FeaturesPerLevel(int num_features, double scale_factor, int num_levels) {
  std::vector<int> per_level(num_levels, 0);
  const double ratio = 1.0 / scale_factor;
  double share = num_features * (1.0 - ratio) / (1.0 - std::pow(ratio, num_levels));
  int assigned = 0;
  for (int level = 0; level + 1 < num_levels; ++level) {
    per_level[level] = std::min(num_features - assigned, static_cast<int>(std::lround(share)));
    assigned += per_level[level];
    share *= ratio;
  }
  per_level[num_levels - 1] = std::max(num_features - assigned, 0);
  return per_level;
}

std::vector<int> AllocateBudgets(const std::vector<int>& desired, const std::vector<int>& available) {
  const int levels = static_cast<int>(desired.size());
  std::vector<int> budget(levels);
  int leftover = 0;
  for (int l = 0; l < levels; ++l) {
    budget[l] = std::min(desired[l], available[l]);
    leftover += desired[l] - budget[l];
  }
  while (leftover > 0) {
    double weight_sum = 0;
    for (int l = 0; l < levels; ++l)
      if (available[l] > budget[l]) weight_sum += std::max(desired[l], 1);
    if (weight_sum == 0) break;
    int handed_out = 0;
    for (int l = 0; l < levels && handed_out < leftover; ++l) {
      const int spare = available[l] - budget[l];
      if (spare <= 0) continue;
      // At least one per level per pass so the loop always progresses.
      const int share = std::max(1, static_cast<int>(leftover * std::max(desired[l], 1) / weight_sum));
      const int extra = std::min({share, spare, leftover - handed_out});
      budget[l] += extra;
      handed_out += extra;
    }
    leftover -= handed_out;
  }
  return budget;
}

namespace {

struct QuadNode {
  float x0, y0, x1, y1;      // [x0, x1) x [y0, y1), level pixels
  std::vector<int> members;  // corner indices
};

bool CanSplit(const QuadNode& node) {
  return node.members.size() > 1 && (node.x1 - node.x0 > 0.5f || node.y1 - node.y0 > 0.5f);
}

// Appends the non-empty quadrants of `node` to `out`.
void Split(const QuadNode& node, const std::vector<cv::KeyPoint>& corners, std::vector<QuadNode>* out) {
  const float xm = 0.5f * (node.x0 + node.x1), ym = 0.5f * (node.y0 + node.y1);
  QuadNode children[4] = {{node.x0, node.y0, xm, ym, {}},
                          {xm, node.y0, node.x1, ym, {}},
                          {node.x0, ym, xm, node.y1, {}},
                          {xm, ym, node.x1, node.y1, {}}};
  for (const int i : node.members) {
    const cv::Point2f& p = corners[i].pt;
    children[(p.x >= xm ? 1 : 0) + (p.y >= ym ? 2 : 0)].members.push_back(i);
  }
  for (auto& child : children)
    if (!child.members.empty()) out->push_back(std::move(child));
}

std::vector<QuadNode> RootNodes(const std::vector<cv::KeyPoint>& corners, const cv::Rect2f& area) {
  const int num_roots = std::max(1, static_cast<int>(std::lround(area.width / area.height)));
  const float root_width = area.width / num_roots;
  std::vector<QuadNode> roots(num_roots);
  for (int r = 0; r < num_roots; ++r)
    roots[r] = {area.x + r * root_width, area.y, area.x + (r + 1) * root_width, area.y + area.height, {}};
  for (int i = 0; i < static_cast<int>(corners.size()); ++i) {
    const cv::Point2f& p = corners[i].pt;
    if (p.x < area.x || p.y < area.y || p.x >= area.x + area.width || p.y >= area.y + area.height) continue;
    const int r = std::min(num_roots - 1, static_cast<int>((p.x - area.x) / root_width));
    roots[r].members.push_back(i);
  }
  roots.erase(std::remove_if(roots.begin(), roots.end(), [](const QuadNode& n) { return n.members.empty(); }),
              roots.end());
  return roots;
}

// One refinement pass. Splits every splittable node, or, when that would overshoot the budget,
// only the most populated ones until the budget is reached. Returns false when nothing split.
bool RefineOnce(const std::vector<cv::KeyPoint>& corners, int budget, std::vector<QuadNode>* nodes) {
  std::vector<int> splittable;
  for (int i = 0; i < static_cast<int>(nodes->size()); ++i)
    if (CanSplit((*nodes)[i])) splittable.push_back(i);
  if (splittable.empty()) return false;
  std::stable_sort(splittable.begin(), splittable.end(), [&](int a, int b) {
    return (*nodes)[a].members.size() > (*nodes)[b].members.size();
  });
  const bool split_all = nodes->size() + 3 * splittable.size() <= static_cast<size_t>(budget);
  std::vector<char> to_split(nodes->size(), 0);
  size_t count = nodes->size();
  for (const int i : splittable) {
    if (!split_all && count >= static_cast<size_t>(budget)) break;
    to_split[i] = 1;
    count += 3;  // upper bound; empty quadrants are dropped
  }
  std::vector<QuadNode> next;
  next.reserve(nodes->size() + 3 * splittable.size());
  for (size_t i = 0; i < nodes->size(); ++i) {
    if (to_split[i])
      Split((*nodes)[i], corners, &next);
    else
      next.push_back(std::move((*nodes)[i]));
  }
  *nodes = std::move(next);
  return true;
}

}  // namespace

std::vector<int> DistributeQuadtree(const std::vector<cv::KeyPoint>& corners, const cv::Rect2f& area,
                                    int budget) {
  if (budget <= 0 || corners.empty() || area.width <= 0 || area.height <= 0) return {};
  std::vector<QuadNode> nodes = RootNodes(corners, area);
  while (nodes.size() < static_cast<size_t>(budget) && RefineOnce(corners, budget, &nodes)) {
  }
  std::vector<int> winners;
  winners.reserve(nodes.size());
  for (const QuadNode& node : nodes) {
    int best = node.members.front();
    for (const int i : node.members)
      if (corners[i].response > corners[best].response) best = i;
    winners.push_back(best);
  }
  if (winners.size() > static_cast<size_t>(budget)) {
    std::stable_sort(winners.begin(), winners.end(),
                     [&](int a, int b) { return corners[a].response > corners[b].response; });
    winners.resize(budget);
  }
  std::sort(winners.begin(), winners.end());
  return winners;
}

}  // namespace esdslam
