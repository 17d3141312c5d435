#pragma once
// Spatial index over undistorted keypoints for radius (square window) queries, as ORB-SLAM2's
// Frame::GetFeaturesInArea: a point i is returned when |u_i - u| < radius and |v_i - v| < radius
// and its level lies in [min_level, max_level] (a bound < 0 means "no bound").

#include <vector>

#include <opencv2/core.hpp>

namespace esdslam {

class FeatureGrid {
 public:
  // Points outside [min_u, max_u) x [min_v, max_v) are still indexed (clamped to border cells).
  FeatureGrid(const std::vector<cv::Point2f>& undistorted_points, const std::vector<int>& levels,
              double min_u, double max_u, double min_v, double max_v, int cols = 64, int rows = 48);

  // Indices of the points in the square window, in increasing index order.
  std::vector<int> FeaturesInArea(double u, double v, double radius, int min_level = -1,
                                  int max_level = -1) const;

  int size() const { return static_cast<int>(points_.size()); }

 private:
  int CellCol(double u) const;
  int CellRow(double v) const;

  std::vector<cv::Point2f> points_;
  std::vector<int> levels_;
  double min_u_, min_v_, cell_width_, cell_height_;
  int cols_, rows_;
  std::vector<std::vector<int>> cells_;  // row-major, cols_ x rows_
};

}  // namespace esdslam
