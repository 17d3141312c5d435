#pragma once
// Relative pose error (Sturm et al. 2012, TUM's evaluate_rpe.py with a fixed delta): for each
// estimate pose i and the pose j one delta later (delta in frames of the estimate, or in
// seconds), with G = ground truth at the same times,
//     E_ij = inverse(inverse(G_i) G_j) * inverse(P_i) P_j
// the translational error is |translation(E_ij)| (m) and the rotational error its angle.
// The ground-truth pose of an estimate time is the nearest ground-truth timestamp within
// max_time_difference (default: twice the median ground-truth interval, as evaluate_rpe.py);
// pairs whose ends have no ground truth are skipped.

#include <cstddef>
#include <vector>

#include "eval/error_stats.h"
#include "io/trajectory_io.h"

namespace esdslam {

struct RpeOptions {
  enum class DeltaUnit { kFrames, kSeconds };
  DeltaUnit unit = DeltaUnit::kFrames;
  double delta = 1.0;                  // frames (integer >= 1) or seconds (> 0)
  double max_time_difference = -1.0;   // seconds; <= 0 means 2 x median ground-truth interval
  double time_offset = 0.0;            // seconds, added to the estimate's timestamps
  void Check() const;
};

struct RpeResult {
  ErrorStats translation_m;
  ErrorStats rotation_deg;
  std::size_t pairs = 0;
};

// Throws Error when no pair can be formed (e.g. trajectory shorter than delta).
RpeResult ComputeRpe(const std::vector<StampedPose>& groundtruth, const std::vector<StampedPose>& estimate,
                     const RpeOptions& options = {});

}  // namespace esdslam
