// ATE on real ground truth (../shared) against an independent implementation: brute-force
// association over all pairs, Horn's closed-form quaternion method (largest eigenvector of the
// 4x4 matrix N) instead of the SVD, and statistics computed separately.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numeric>
#include <random>
#include <tuple>

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include "eval/ate.h"
#include "io/test_files.h"
#include "io/trajectory_io.h"
#include "support/test_paths.h"

namespace esdslam {
namespace {

struct ReferenceAte {
  std::vector<double> errors;
  double scale = 1;
  Mat3 rotation = Mat3::Identity();
};

std::vector<std::pair<std::size_t, std::size_t>> BruteForceAssociate(const std::vector<StampedPose>& estimate,
                                                                     const std::vector<StampedPose>& groundtruth,
                                                                     double max_dt) {
  std::vector<std::tuple<double, double, double, std::size_t, std::size_t>> candidates;
  for (std::size_t i = 0; i < estimate.size(); ++i) {
    for (std::size_t j = 0; j < groundtruth.size(); ++j) {
      const double dt = std::abs(estimate[i].timestamp - groundtruth[j].timestamp);
      if (dt <= max_dt + 1e-9) candidates.emplace_back(dt, estimate[i].timestamp, groundtruth[j].timestamp, i, j);
    }
  }
  std::sort(candidates.begin(), candidates.end());
  std::vector<char> used_est(estimate.size(), 0), used_gt(groundtruth.size(), 0);
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  for (const auto& [dt, te, tg, i, j] : candidates) {
    if (used_est[i] || used_gt[j]) continue;
    used_est[i] = used_gt[j] = 1;
    pairs.emplace_back(i, j);
  }
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

// Horn (1987): the rotation maximising sum d_c . R m_c is the eigenvector of the largest
// eigenvalue of N(S), S = sum m_c d_c^T; scale (when asked) = sum d_c . R m_c / sum |m_c|^2.
ReferenceAte HornAte(const std::vector<Vec3>& model, const std::vector<Vec3>& data, bool with_scale) {
  const Vec3 model_mean = std::accumulate(model.begin(), model.end(), Vec3(Vec3::Zero())) / double(model.size());
  const Vec3 data_mean = std::accumulate(data.begin(), data.end(), Vec3(Vec3::Zero())) / double(data.size());
  Mat3 s = Mat3::Zero();
  for (std::size_t k = 0; k < model.size(); ++k) s += (model[k] - model_mean) * (data[k] - data_mean).transpose();
  Eigen::Matrix4d n;
  n << s(0, 0) + s(1, 1) + s(2, 2), s(1, 2) - s(2, 1), s(2, 0) - s(0, 2), s(0, 1) - s(1, 0),
      s(1, 2) - s(2, 1), s(0, 0) - s(1, 1) - s(2, 2), s(0, 1) + s(1, 0), s(2, 0) + s(0, 2),
      s(2, 0) - s(0, 2), s(0, 1) + s(1, 0), -s(0, 0) + s(1, 1) - s(2, 2), s(1, 2) + s(2, 1),
      s(0, 1) - s(1, 0), s(2, 0) + s(0, 2), s(1, 2) + s(2, 1), -s(0, 0) - s(1, 1) + s(2, 2);
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> solver(n);
  const Eigen::Vector4d q = solver.eigenvectors().col(3);  // eigenvalues ascending
  ReferenceAte result;
  result.rotation = Quat(q(0), q(1), q(2), q(3)).normalized().toRotationMatrix();
  if (with_scale) {
    double numerator = 0, denominator = 0;
    for (std::size_t k = 0; k < model.size(); ++k) {
      numerator += (data[k] - data_mean).dot(result.rotation * (model[k] - model_mean));
      denominator += (model[k] - model_mean).squaredNorm();
    }
    result.scale = numerator / denominator;
  }
  const Vec3 translation = data_mean - result.scale * result.rotation * model_mean;
  for (std::size_t k = 0; k < model.size(); ++k) {
    result.errors.push_back((data[k] - (result.scale * result.rotation * model[k] + translation)).norm());
  }
  return result;
}

// Estimate = transform * ground truth, positions with N(0, 1 cm) noise, times jittered by up
// to +-4 ms, every 7th pose dropped, optionally scaled by 0.8; written and read back as a file.
std::vector<StampedPose> MakeEstimate(const std::vector<StampedPose>& groundtruth, double scale,
                                      const std::string& path) {
  const Rigid3 transform(Quat(Eigen::AngleAxisd(2.1, Vec3(0.3, 0.9, -0.2).normalized())), Vec3(-3, 4, 1.5));
  std::mt19937 rng(42);
  std::normal_distribution<double> noise(0.0, 0.01);
  std::uniform_real_distribution<double> jitter(-0.004, 0.004);
  std::vector<StampedPose> estimate;
  for (std::size_t i = 0; i < groundtruth.size(); ++i) {
    const Vec3 noisy = groundtruth[i].world_from_cam.translation() + Vec3(noise(rng), noise(rng), noise(rng));
    const double t = groundtruth[i].timestamp + jitter(rng);
    if (i % 7 == 3) continue;
    const Rigid3 pose(groundtruth[i].world_from_cam.rotation(), scale * noisy);
    estimate.push_back({t, transform * pose});
  }
  WriteTumTrajectory(path, estimate);
  return ReadTumTrajectory(path);
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

void CompareOnSequence(const std::string& sequence, bool with_scale) {
  const std::string gt_path = ::esdslam::testing::TestDataDir() + "/data/" + sequence + "/groundtruth.txt";
  if (!std::filesystem::exists(gt_path)) GTEST_SKIP() << "no data at " << gt_path;
  testing::TempDir dir;
  const std::vector<StampedPose> groundtruth = ReadTumTrajectory(gt_path);
  const std::vector<StampedPose> estimate = MakeEstimate(groundtruth, with_scale ? 0.8 : 1.0, dir.Path("est.txt"));
  AteOptions options;
  options.with_scale = with_scale;
  const AteResult result = ComputeAte(groundtruth, estimate, options);

  const auto pairs = BruteForceAssociate(estimate, groundtruth, 0.02);
  std::vector<Vec3> model, data;
  for (const auto& [i, j] : pairs) {
    model.push_back(estimate[i].world_from_cam.translation());
    data.push_back(groundtruth[j].world_from_cam.translation());
  }
  const ReferenceAte reference = HornAte(model, data, with_scale);
  const auto& e = reference.errors;
  const double n = double(e.size());
  const double mean = std::accumulate(e.begin(), e.end(), 0.0) / n;
  const double rmse = std::sqrt(std::inner_product(e.begin(), e.end(), e.begin(), 0.0) / n);
  const double std_dev = std::sqrt(rmse * rmse - mean * mean);

  ASSERT_EQ(result.pairs.size(), pairs.size());
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    ASSERT_EQ(result.pairs[k].estimate_index, pairs[k].first);
    ASSERT_EQ(result.pairs[k].groundtruth_index, pairs[k].second);
  }
  EXPECT_NEAR(result.translation_m.rmse, rmse, 1e-6);
  EXPECT_NEAR(result.translation_m.mean, mean, 1e-6);
  EXPECT_NEAR(result.translation_m.median, Median(e), 1e-6);
  EXPECT_NEAR(result.translation_m.std, std_dev, 1e-6);
  EXPECT_NEAR(result.translation_m.min, *std::min_element(e.begin(), e.end()), 1e-6);
  EXPECT_NEAR(result.translation_m.max, *std::max_element(e.begin(), e.end()), 1e-6);
  EXPECT_NEAR(result.groundtruth_from_estimate.scale, reference.scale, 1e-6);
  EXPECT_NEAR((result.groundtruth_from_estimate.rotation - reference.rotation).norm(), 0, 1e-6);
  // Sanity: 1 cm isotropic noise gives about sqrt(3) cm after alignment; most poses pair up.
  EXPECT_GT(result.translation_m.rmse, 0.012);
  EXPECT_LT(result.translation_m.rmse, 0.020);
  EXPECT_GT(pairs.size(), estimate.size() * 8 / 10);
  std::printf("%s scale=%d: pairs %zu/%zu, ate_rmse %.6f (reference %.6f)\n", sequence.c_str(), int(with_scale),
              pairs.size(), estimate.size(), result.translation_m.rmse, rmse);
}

TEST(AteSlow, AgreesWithHornQuaternionMethodOnTumFr1Rpy) { CompareOnSequence("tum_fr1_rpy_dev", false); }
TEST(AteSlow, AgreesWithHornQuaternionMethodOnBonnCrowd) { CompareOnSequence("bonn_crowd_dev", false); }
TEST(AteSlow, AgreesWithHornWithScaleOnTumFr1Rpy) { CompareOnSequence("tum_fr1_rpy_dev", true); }
TEST(AteSlow, AgreesWithHornWithScaleOnBonnCrowd) { CompareOnSequence("bonn_crowd_dev", true); }

}  // namespace
}  // namespace esdslam
