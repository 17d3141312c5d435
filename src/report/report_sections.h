#pragma once
// The sections of the run report (report/run_report.h), each an HTML fragment (<section>).
// Times on the x axes are seconds since the first frame of timing.csv (ReportData::t0).

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "eval/report.h"
#include "report/run_files.h"
#include "report/run_report.h"

namespace esdslam {

struct ReportData {
  const RunFiles* files = nullptr;
  const std::vector<StampedPose>* groundtruth = nullptr;  // nullptr = none
  std::optional<EvalReport> eval;                          // with ground truth
  double t0 = 0;                                           // seconds
  std::vector<std::pair<double, double>> crowded;          // shaded intervals, seconds since t0
  std::size_t crowded_frames = 0;
};

// The frames of timing.csv whose dynamic_fraction exceeds `fraction`, as merged time intervals
// (seconds since t0), each frame widened by half the median frame interval on both sides.
// No dynamic_fraction column: none.
std::vector<std::pair<double, double>> CrowdedIntervals(const TimingTable& timing, double fraction, double t0,
                                                        std::size_t* frames);

// Debug pictures to show: up to `count`, evenly spaced over the run, one of them the picture of
// the most crowded frame; sorted by time.
std::vector<std::size_t> SampleDebugPictures(const std::vector<DebugPicture>& pictures, const TimingTable& timing,
                                             int count);

std::string TrajectorySection(const ReportData& data);
std::string ErrorSection(const ReportData& data, const ReportOptions& options);
std::string TimingSection(const ReportData& data, const ReportOptions& options);
std::string DebugSection(const ReportData& data, const ReportOptions& options);
std::string SummarySection(const ReportData& data, const ReportOptions& options);
std::string SettingsSection(const ReportData& data);

}  // namespace esdslam
