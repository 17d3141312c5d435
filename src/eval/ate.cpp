#include "eval/ate.h"

#include "common/error.h"
#include "io/associate.h"

namespace esdslam {

void AteOptions::Check() const {
  if (!(max_time_difference > 0)) throw Error("ATE max_time_difference must be > 0 seconds");
}

AteResult ComputeAte(const std::vector<StampedPose>& groundtruth, const std::vector<StampedPose>& estimate,
                     const AteOptions& options) {
  options.Check();
  std::vector<double> estimate_times, groundtruth_times;
  for (const auto& pose : estimate) estimate_times.push_back(pose.timestamp);
  for (const auto& pose : groundtruth) groundtruth_times.push_back(pose.timestamp);
  // Offset is on the estimate side: |(t_est + offset) - t_gt| <= max.
  const std::vector<TimestampMatch> matches =
      AssociateTimestamps(estimate_times, groundtruth_times, options.max_time_difference, -options.time_offset);
  if (matches.size() < 3) {
    throw Error(fmt::format("ATE: only {} estimate poses have ground truth within {} s (need >= 3); "
                            "check that the files belong to the same sequence",
                            matches.size(), options.max_time_difference));
  }
  std::vector<Vec3> estimate_positions, groundtruth_positions;
  for (const TimestampMatch& m : matches) {
    estimate_positions.push_back(estimate[m.first].world_from_cam.translation());
    groundtruth_positions.push_back(groundtruth[m.second].world_from_cam.translation());
  }
  AteResult result;
  result.groundtruth_from_estimate = AlignPoints(estimate_positions, groundtruth_positions, options.with_scale);
  std::vector<double> errors;
  for (std::size_t k = 0; k < matches.size(); ++k) {
    const double error =
        (groundtruth_positions[k] - result.groundtruth_from_estimate * estimate_positions[k]).norm();
    errors.push_back(error);
    result.pairs.push_back({matches[k].first, matches[k].second, error});
  }
  result.translation_m = ComputeErrorStats(errors);
  return result;
}

}  // namespace esdslam
