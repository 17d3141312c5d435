#include "dense/outlier_filter.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <unordered_map>

namespace esdslam {

namespace {

// Buckets point indices by cubic cell of side `cell` for neighbourhood queries.
class SpatialHash {
 public:
  SpatialHash(const PointCloud& cloud, double cell) : cloud_(cloud), cell_(cell) {
    for (std::size_t i = 0; i < cloud.size(); ++i) cells_[Key(Cell(cloud.points[i]))].push_back(static_cast<std::uint32_t>(i));
  }

  // Squared distances from point i to its k nearest other points within the 27 neighbouring
  // cells, ascending (fewer than k when the neighbourhood is sparse).
  void Nearest(std::size_t i, int k, std::vector<float>* sq_distances) const {
    sq_distances->clear();
    const Eigen::Vector3f& p = cloud_.points[i];
    const Eigen::Vector3i c = Cell(p);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const auto it = cells_.find(Key(c + Eigen::Vector3i(dx, dy, dz)));
          if (it == cells_.end()) continue;
          for (const std::uint32_t j : it->second)
            if (j != i) sq_distances->push_back((cloud_.points[j] - p).squaredNorm());
        }
    const std::size_t keep = std::min<std::size_t>(k, sq_distances->size());
    std::partial_sort(sq_distances->begin(), sq_distances->begin() + keep, sq_distances->end());
    sq_distances->resize(keep);
  }

 private:
  Eigen::Vector3i Cell(const Eigen::Vector3f& p) const {
    return Eigen::Vector3i(static_cast<int>(std::floor(p.x() / cell_)), static_cast<int>(std::floor(p.y() / cell_)),
                           static_cast<int>(std::floor(p.z() / cell_)));
  }
  static std::uint64_t Key(const Eigen::Vector3i& c) {
    const auto pack = [](int v) { return static_cast<std::uint64_t>(static_cast<std::uint32_t>(v + (1 << 20)) & 0x1FFFFF); };
    return (pack(c.x()) << 42) | (pack(c.y()) << 21) | pack(c.z());
  }

  const PointCloud& cloud_;
  double cell_;
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> cells_;
};

}  // namespace

PointCloud RemoveStatisticalOutliers(const PointCloud& cloud, const OutlierFilterOptions& options) {
  if (cloud.size() < 2) return cloud;
  const SpatialHash hash(cloud, options.search_radius);
  const float no_neighbours = std::numeric_limits<float>::infinity();
  std::vector<float> mean_distance(cloud.size(), no_neighbours);
  std::vector<float> sq;
  double sum = 0, sum_sq = 0;
  std::size_t counted = 0;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    hash.Nearest(i, options.neighbors, &sq);
    if (static_cast<int>(sq.size()) < options.neighbors) continue;
    double d = 0;
    for (const float s : sq) d += std::sqrt(s);
    mean_distance[i] = static_cast<float>(d / sq.size());
    sum += mean_distance[i];
    sum_sq += static_cast<double>(mean_distance[i]) * mean_distance[i];
    ++counted;
  }
  if (counted == 0) return PointCloud{};
  const double mean = sum / counted;
  const double stddev = std::sqrt(std::max(0.0, sum_sq / counted - mean * mean));
  const double limit = mean + options.std_ratio * stddev;
  PointCloud kept;
  kept.reserve(counted);
  for (std::size_t i = 0; i < cloud.size(); ++i)
    if (mean_distance[i] <= limit) kept.push_back(cloud.points[i], cloud.colors[i]);
  return kept;
}

}  // namespace esdslam
