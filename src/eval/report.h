#pragma once
// The full evaluation that `esdslam eval` prints (and the run command may reuse): ATE, RPE per
// frame (delta 1 frame) and RPE per second (delta 1 s), as text lines 'name value' or JSON.

#include <optional>
#include <string>
#include <vector>

#include "eval/ate.h"
#include "eval/rpe.h"

namespace esdslam {

struct EvalOptions {
  AteOptions ate;
  // RPE variants use ate.max_time_difference only if rpe_max_time_difference > 0.
  double rpe_max_time_difference = -1.0;
};

struct EvalReport {
  AteResult ate;
  std::optional<RpeResult> rpe_per_frame;   // absent when no pair could be formed
  std::optional<RpeResult> rpe_per_second;  // absent e.g. for trajectories shorter than 1 s
};

EvalReport Evaluate(const std::vector<StampedPose>& groundtruth, const std::vector<StampedPose>& estimate,
                    const EvalOptions& options = {});

// Ordered (name, value) metrics: ate_rmse ate_mean ate_median ate_std ate_min ate_max pairs,
// rpe_frame_trans_{rmse,mean,median} rpe_frame_rot_{rmse,mean,median}_deg rpe_frame_pairs, and
// the same with rpe_second_. Lengths in metres.
std::vector<std::pair<std::string, double>> ReportMetrics(const EvalReport& report);
// A metric's value as the text and JSON print it: counts (names ending in "pairs") as integers,
// the rest with 9 significant digits.
std::string FormatMetricValue(const std::string& name, double value);
std::string FormatReportText(const EvalReport& report);  // one 'name value' per line
std::string FormatReportJson(const EvalReport& report);  // one flat JSON object

}  // namespace esdslam
