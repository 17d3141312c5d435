#include "feature/feature_grid.h"

#include <algorithm>
#include <cmath>

#include "common/error.h"

namespace esdslam {

FeatureGrid::FeatureGrid(const std::vector<cv::Point2f>& undistorted_points, const std::vector<int>& levels,
                         double min_u, double max_u, double min_v, double max_v, int cols, int rows)
    : points_(undistorted_points), levels_(levels), min_u_(min_u), min_v_(min_v), cols_(cols), rows_(rows) {
  if (levels.size() != undistorted_points.size())
    throw Error("FeatureGrid: one level per point expected");
  if (cols <= 0 || rows <= 0 || !(max_u > min_u) || !(max_v > min_v))
    throw Error("FeatureGrid: empty grid bounds or cell counts");
  cell_width_ = (max_u - min_u) / cols;
  cell_height_ = (max_v - min_v) / rows;
  cells_.resize(static_cast<size_t>(cols) * rows);
  for (int i = 0; i < static_cast<int>(points_.size()); ++i) {
    cells_[static_cast<size_t>(CellRow(points_[i].y)) * cols_ + CellCol(points_[i].x)].push_back(i);
  }
}

int FeatureGrid::CellCol(double u) const {
  const double col = std::floor((u - min_u_) / cell_width_);
  if (!(col > 0)) return 0;  // also NaN
  return col >= cols_ - 1 ? cols_ - 1 : static_cast<int>(col);
}

int FeatureGrid::CellRow(double v) const {
  const double row = std::floor((v - min_v_) / cell_height_);
  if (!(row > 0)) return 0;  // also NaN
  return row >= rows_ - 1 ? rows_ - 1 : static_cast<int>(row);
}

std::vector<int> FeatureGrid::FeaturesInArea(double u, double v, double radius, int min_level,
                                             int max_level) const {
  std::vector<int> result;
  if (!(radius > 0) || !std::isfinite(u) || !std::isfinite(v)) return result;
  // Cells are clamped, so border cells also hold the points outside the bounds.
  const int col_begin = CellCol(u - radius), col_end = CellCol(u + radius);
  const int row_begin = CellRow(v - radius), row_end = CellRow(v + radius);
  for (int row = row_begin; row <= row_end; ++row) {
    for (int col = col_begin; col <= col_end; ++col) {
      for (const int i : cells_[static_cast<size_t>(row) * cols_ + col]) {
        if (min_level >= 0 && levels_[i] < min_level) continue;
        if (max_level >= 0 && levels_[i] > max_level) continue;
        if (std::abs(points_[i].x - u) < radius && std::abs(points_[i].y - v) < radius) result.push_back(i);
      }
    }
  }
  std::sort(result.begin(), result.end());
  return result;
}

}  // namespace esdslam
