#include "eval/alignment.h"

#include <Eigen/SVD>

#include "common/error.h"

namespace esdslam {

Similarity3 AlignPoints(const std::vector<Vec3>& source, const std::vector<Vec3>& target, bool with_scale) {
  if (source.size() != target.size()) throw Error("AlignPoints: point lists differ in size");
  if (source.size() < 3) throw Error("AlignPoints: need at least 3 point pairs");
  const double n = static_cast<double>(source.size());
  Vec3 source_mean = Vec3::Zero(), target_mean = Vec3::Zero();
  for (std::size_t i = 0; i < source.size(); ++i) {
    source_mean += source[i];
    target_mean += target[i];
  }
  source_mean /= n;
  target_mean /= n;
  // Cross-covariance sum (target - mean)(source - mean)^T / n and source variance.
  Mat3 covariance = Mat3::Zero();
  double source_variance = 0;
  for (std::size_t i = 0; i < source.size(); ++i) {
    const Vec3 s = source[i] - source_mean;
    covariance += (target[i] - target_mean) * s.transpose();
    source_variance += s.squaredNorm();
  }
  covariance /= n;
  source_variance /= n;
  const Eigen::JacobiSVD<Mat3> svd(covariance, Eigen::ComputeFullU | Eigen::ComputeFullV);
  // Reflection guard: force det(R) = +1 by flipping the weakest singular direction.
  Vec3 signs(1, 1, 1);
  if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0) signs.z() = -1;
  Similarity3 result;
  result.rotation = svd.matrixU() * signs.asDiagonal() * svd.matrixV().transpose();
  if (with_scale) {
    if (!(source_variance > 0)) throw Error("AlignPoints: source points coincide, scale undefined");
    result.scale = svd.singularValues().dot(signs) / source_variance;
  }
  result.translation = target_mean - result.scale * (result.rotation * source_mean);
  return result;
}

}  // namespace esdslam
