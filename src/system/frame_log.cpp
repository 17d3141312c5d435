#include "system/frame_log.h"

#include <algorithm>
#include <fstream>

#include <fmt/format.h>

#include "common/error.h"
#include "system/frame_columns.h"

namespace esdslam {

void FrameLog::Add(const FrameReport& report) { rows_.push_back(ReadFrameColumns(report)); }

std::vector<double> FrameLog::Values(const std::string& column) const {
  const std::size_t index = FrameColumnIndex(column);
  std::vector<double> values;
  values.reserve(rows_.size());
  for (const std::vector<double>& row : rows_) values.push_back(row[index]);
  return values;
}

void FrameLog::WriteCsv(const std::string& path) const {
  std::ofstream out(path);
  if (!out) throw Error("cannot write " + path);
  out << FrameCsvHeader() << '\n';
  for (const std::vector<double>& row : rows_) out << FrameCsvRow(row) << '\n';
  if (!out) throw Error("cannot write " + path);
}

MeanMedian ComputeMeanMedian(std::vector<double> values) {
  if (values.empty()) return {};
  MeanMedian stats;
  for (double v : values) stats.mean += v / values.size();
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  stats.median = values[values.size() / 2];
  return stats;
}

std::string FormatStageSummary(const FrameLog& log) {
  std::string text;
  for (const FrameColumn& column : FrameColumns()) {
    if (column.summary == nullptr) continue;
    const MeanMedian stats = ComputeMeanMedian(log.Values(column.name));
    text += fmt::format("{:<8} mean {:7.2f} {}  median {:7.2f} {}\n", column.summary, stats.mean, column.unit,
                        stats.median, column.unit);
  }
  return text;
}

}  // namespace esdslam
