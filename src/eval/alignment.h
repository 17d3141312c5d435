#pragma once
// Closed-form least-squares alignment of two point sets (Horn 1987 / Umeyama 1991, via SVD of
// the cross-covariance): finds scale s, rotation R, translation t minimising
// sum |target_i - (s R source_i + t)|^2. Without scale, s = 1 (rigid, as TUM's evaluate_ate.py).

#include <vector>

#include "common/geometry.h"

namespace esdslam {

struct Similarity3 {
  double scale = 1.0;
  Mat3 rotation = Mat3::Identity();
  Vec3 translation = Vec3::Zero();
  Vec3 operator*(const Vec3& p) const { return scale * (rotation * p) + translation; }
};

// target_from_source. Throws Error when sizes differ or fewer than 3 points are given.
// Degenerate sets (collinear points) give a valid minimiser, not unique in rotation.
Similarity3 AlignPoints(const std::vector<Vec3>& source, const std::vector<Vec3>& target, bool with_scale);

}  // namespace esdslam
