#pragma once
// A coloured point cloud: parallel arrays of positions (metres, in the frame the owner states)
// and colours (8-bit RGB).

#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "common/geometry.h"

namespace esdslam {

struct Rgb8 {
  std::uint8_t r = 0, g = 0, b = 0;
};

struct PointCloud {
  std::vector<Eigen::Vector3f> points;
  std::vector<Rgb8> colors;

  std::size_t size() const { return points.size(); }
  bool empty() const { return points.empty(); }
  void reserve(std::size_t n) {
    points.reserve(n);
    colors.reserve(n);
  }
  void push_back(const Eigen::Vector3f& p, const Rgb8& c) {
    points.push_back(p);
    colors.push_back(c);
  }
};

// Returns `cloud` with every point mapped through `to_from_cloud` (cloud frame -> target frame).
PointCloud TransformCloud(const PointCloud& cloud, const Rigid3& to_from_cloud);

}  // namespace esdslam
