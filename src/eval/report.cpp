#include "eval/report.h"

#include <cmath>

#include <spdlog/spdlog.h>

#include "common/error.h"

namespace esdslam {
namespace {

std::optional<RpeResult> TryRpe(const std::vector<StampedPose>& groundtruth, const std::vector<StampedPose>& estimate,
                                const RpeOptions& options, const char* label) {
  try {
    return ComputeRpe(groundtruth, estimate, options);
  } catch (const Error& e) {
    spdlog::warn("RPE {} not computed: {}", label, e.what());
    return std::nullopt;
  }
}

void AddRpe(const std::optional<RpeResult>& rpe, const std::string& prefix,
            std::vector<std::pair<std::string, double>>& metrics) {
  if (!rpe) return;
  metrics.emplace_back(prefix + "_trans_rmse", rpe->translation_m.rmse);
  metrics.emplace_back(prefix + "_trans_mean", rpe->translation_m.mean);
  metrics.emplace_back(prefix + "_trans_median", rpe->translation_m.median);
  metrics.emplace_back(prefix + "_rot_rmse_deg", rpe->rotation_deg.rmse);
  metrics.emplace_back(prefix + "_rot_mean_deg", rpe->rotation_deg.mean);
  metrics.emplace_back(prefix + "_rot_median_deg", rpe->rotation_deg.median);
  metrics.emplace_back(prefix + "_pairs", static_cast<double>(rpe->pairs));
}

bool IsCount(const std::string& name) { return name.size() >= 5 && name.compare(name.size() - 5, 5, "pairs") == 0; }

}  // namespace

std::string FormatMetricValue(const std::string& name, double value) {
  return IsCount(name) ? fmt::format("{}", static_cast<long long>(value)) : fmt::format("{:.9g}", value);
}

EvalReport Evaluate(const std::vector<StampedPose>& groundtruth, const std::vector<StampedPose>& estimate,
                    const EvalOptions& options) {
  EvalReport report;
  report.ate = ComputeAte(groundtruth, estimate, options.ate);
  RpeOptions rpe;
  rpe.time_offset = options.ate.time_offset;
  rpe.max_time_difference = options.rpe_max_time_difference;
  rpe.unit = RpeOptions::DeltaUnit::kFrames;
  rpe.delta = 1;
  report.rpe_per_frame = TryRpe(groundtruth, estimate, rpe, "per frame");
  rpe.unit = RpeOptions::DeltaUnit::kSeconds;
  rpe.delta = 1.0;
  report.rpe_per_second = TryRpe(groundtruth, estimate, rpe, "per second");
  return report;
}

std::vector<std::pair<std::string, double>> ReportMetrics(const EvalReport& report) {
  const ErrorStats& ate = report.ate.translation_m;
  std::vector<std::pair<std::string, double>> metrics = {
      {"ate_rmse", ate.rmse}, {"ate_mean", ate.mean}, {"ate_median", ate.median}, {"ate_std", ate.std},
      {"ate_min", ate.min},   {"ate_max", ate.max},   {"pairs", static_cast<double>(ate.count)}};
  if (report.ate.groundtruth_from_estimate.scale != 1.0) {
    metrics.emplace_back("scale", report.ate.groundtruth_from_estimate.scale);
  }
  AddRpe(report.rpe_per_frame, "rpe_frame", metrics);
  AddRpe(report.rpe_per_second, "rpe_second", metrics);
  return metrics;
}

std::string FormatReportText(const EvalReport& report) {
  std::string text;
  for (const auto& [name, value] : ReportMetrics(report)) text += name + " " + FormatMetricValue(name, value) + "\n";
  return text;
}

std::string FormatReportJson(const EvalReport& report) {
  std::string json = "{";
  bool first = true;
  for (const auto& [name, value] : ReportMetrics(report)) {
    json += fmt::format("{}\n  \"{}\": {}", first ? "" : ",", name, FormatMetricValue(name, value));
    first = false;
  }
  return json + "\n}\n";
}

}  // namespace esdslam
