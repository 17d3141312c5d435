#pragma once
// Absolute trajectory error as the TUM RGB-D benchmark defines it (evaluate_ate.py): associate
// estimate and ground-truth poses by timestamp (greedy nearest, |dt| <= max_time_difference),
// align the estimate positions to the ground-truth positions (rigid, or similarity with
// with_scale), and take per-pair translational error |p_gt - S p_est| in metres.

#include <cstddef>
#include <vector>

#include "eval/alignment.h"
#include "eval/error_stats.h"
#include "io/trajectory_io.h"

namespace esdslam {

struct AteOptions {
  double max_time_difference = 0.02;  // seconds
  double time_offset = 0.0;           // seconds, added to the estimate's timestamps
  bool with_scale = false;            // similarity alignment (monocular-style)
  void Check() const;
};

struct AtePair {
  std::size_t estimate_index = 0;
  std::size_t groundtruth_index = 0;
  double error_m = 0;
};

struct AteResult {
  ErrorStats translation_m;        // over all pairs
  Similarity3 groundtruth_from_estimate;
  std::vector<AtePair> pairs;      // sorted by estimate time
};

// Throws Error when fewer than 3 pairs associate.
AteResult ComputeAte(const std::vector<StampedPose>& groundtruth, const std::vector<StampedPose>& estimate,
                     const AteOptions& options = {});

}  // namespace esdslam
