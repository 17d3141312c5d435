#pragma once
// The per-frame values of a run, one row per frame in the order of the column table
// (system/frame_columns.h). Only numbers are kept (no images), so a run of any length fits.
// timing.csv and the summary's per-stage lines are made from it; a benchmark reads columns by
// name (Values) for its statistics.

#include <string>
#include <vector>

#include "system/frame_report.h"

namespace esdslam {

class FrameLog {
 public:
  void Add(const FrameReport& report);  // reads every column of the table
  std::size_t size() const { return rows_.size(); }
  bool empty() const { return rows_.empty(); }
  const std::vector<double>& row(std::size_t i) const { return rows_.at(i); }
  // The named column's value of every frame, in order. Throws Error on an unknown name.
  std::vector<double> Values(const std::string& column) const;
  // timing.csv: the header, then one line per frame. Throws Error when the file cannot be written.
  void WriteCsv(const std::string& path) const;

 private:
  std::vector<std::vector<double>> rows_;
};

struct MeanMedian {
  double mean = 0;
  double median = 0;  // the upper middle value for an even count
};
MeanMedian ComputeMeanMedian(std::vector<double> values);  // zeros for no values

// One line per column with a summary label, in table order:
// "load     mean   10.26 ms  median    9.97 ms".
std::string FormatStageSummary(const FrameLog& log);

}  // namespace esdslam
