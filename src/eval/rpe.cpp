#include "eval/rpe.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "common/error.h"

namespace esdslam {
namespace {

constexpr double kPi = 3.14159265358979323846;

std::vector<double> Times(const std::vector<StampedPose>& poses, const char* name) {
  std::vector<double> times;
  for (const auto& pose : poses) times.push_back(pose.timestamp);
  for (std::size_t i = 1; i < times.size(); ++i) {
    if (!(times[i] > times[i - 1])) throw Error(fmt::format("RPE: {} timestamps must be strictly increasing", name));
  }
  return times;
}

// Rotation angle in degrees, accurate near zero (atan2 instead of acos of w).
double AngleDegrees(const Quat& rotation) {
  return 2.0 * std::atan2(rotation.vec().norm(), std::abs(rotation.w())) * 180.0 / kPi;
}

// Index of the element of sorted `times` nearest to t (ties: the earlier one).
std::size_t NearestIndex(const std::vector<double>& times, double t) {
  const auto it = std::lower_bound(times.begin(), times.end(), t);
  if (it == times.begin()) return 0;
  if (it == times.end()) return times.size() - 1;
  const std::size_t after = static_cast<std::size_t>(it - times.begin());
  return (t - times[after - 1] <= times[after] - t) ? after - 1 : after;
}

double MedianInterval(const std::vector<double>& times) {
  if (times.size() < 2) throw Error("RPE: ground truth needs at least 2 poses");
  std::vector<double> intervals;
  for (std::size_t i = 1; i < times.size(); ++i) intervals.push_back(times[i] - times[i - 1]);
  return ComputeErrorStats(intervals).median;
}

// The second index of the pair starting at i, or nullopt when it falls past the end.
std::optional<std::size_t> PairEnd(const std::vector<double>& times, std::size_t i, const RpeOptions& options) {
  if (options.unit == RpeOptions::DeltaUnit::kFrames) {
    const std::size_t j = i + static_cast<std::size_t>(std::llround(options.delta));
    return j < times.size() ? std::optional<std::size_t>(j) : std::nullopt;
  }
  const double target = times[i] + options.delta;
  if (target > times.back() + 1e-9) return std::nullopt;
  const std::size_t j = NearestIndex(times, target);
  return j > i ? std::optional<std::size_t>(j) : std::nullopt;
}

}  // namespace

void RpeOptions::Check() const {
  if (!(delta > 0)) throw Error("RPE delta must be > 0");
  if (unit == DeltaUnit::kFrames && (delta < 1 || delta != std::floor(delta))) {
    throw Error("RPE delta in frames must be a positive integer");
  }
}

RpeResult ComputeRpe(const std::vector<StampedPose>& groundtruth, const std::vector<StampedPose>& estimate,
                     const RpeOptions& options) {
  options.Check();
  const std::vector<double> estimate_times = Times(estimate, "estimate");
  const std::vector<double> groundtruth_times = Times(groundtruth, "ground-truth");
  const double max_dt =
      options.max_time_difference > 0 ? options.max_time_difference : 2.0 * MedianInterval(groundtruth_times);
  // Ground-truth index for each estimate pose, if one is close enough.
  std::vector<std::optional<std::size_t>> gt_index(estimate.size());
  for (std::size_t i = 0; i < estimate.size(); ++i) {
    const double t = estimate_times[i] + options.time_offset;
    const std::size_t k = NearestIndex(groundtruth_times, t);
    if (std::abs(groundtruth_times[k] - t) <= max_dt + 1e-9) gt_index[i] = k;
  }
  std::vector<double> translation_errors, rotation_errors;
  for (std::size_t i = 0; i < estimate.size(); ++i) {
    const std::optional<std::size_t> j = PairEnd(estimate_times, i, options);
    if (!j || !gt_index[i] || !gt_index[*j]) continue;
    const Rigid3 gt_motion =
        groundtruth[*gt_index[i]].world_from_cam.inverse() * groundtruth[*gt_index[*j]].world_from_cam;
    const Rigid3 est_motion = estimate[i].world_from_cam.inverse() * estimate[*j].world_from_cam;
    const Rigid3 error = gt_motion.inverse() * est_motion;
    translation_errors.push_back(error.translation().norm());
    rotation_errors.push_back(AngleDegrees(error.rotation()));
  }
  if (translation_errors.empty()) {
    throw Error("RPE: no pose pair with ground truth at both ends (trajectory shorter than delta?)");
  }
  RpeResult result;
  result.translation_m = ComputeErrorStats(translation_errors);
  result.rotation_deg = ComputeErrorStats(rotation_errors);
  result.pairs = translation_errors.size();
  return result;
}

}  // namespace esdslam
