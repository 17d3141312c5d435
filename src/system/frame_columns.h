#pragma once
// The ONE table of per-frame columns: name, unit, format and how to read it from a FrameReport,
// and whether the end-of-run summary gives its mean and median. It drives
//   - timing.csv (the columns with csv = true, in table order; system/frame_log.h),
//   - the summary's per-stage lines (summary label set, in table order),
//   - any other reader that wants per-frame numbers by name: a live viewer's stage times (the
//     columns in "ms"), a benchmark's per-stage statistics (FrameLog::Values).
// Names are the timing.csv header (readers find columns by name, never by position). A new
// column is one row in the table (frame_columns.cpp) plus its line in the README's timing.csv
// table; tests/system/frame_columns_test.cpp checks the README lists every CSV column.

#include <string>
#include <vector>

#include "system/frame_report.h"

namespace esdslam {

struct FrameColumn {
  const char* name;  // timing.csv header
  const char* unit;  // "s", "ms", "px", "frames"; "" for counts, fractions and text
  // CSV format: fixed-point with this many decimals; kInteger prints the value as an integer.
  int decimals;
  double (*read)(const FrameReport& report);  // the column's value (text columns: an enum value)
  const char* summary = nullptr;  // label of its mean/median line in the summary; nullptr = none
  bool csv = true;                // false: summary and readers only (a sum of other columns)
  const char* (*text)(double value) = nullptr;  // CSV text for the value instead of a number (state)

  static constexpr int kInteger = -1;
  std::string Format(double value) const;  // as written to timing.csv
};

// Every column, in timing.csv order; summary-only columns last.
const std::vector<FrameColumn>& FrameColumns();
// The column named `name`; throws Error when there is none.
const FrameColumn& FindFrameColumn(const std::string& name);
// Index of `name` in FrameColumns(); throws Error when there is none.
std::size_t FrameColumnIndex(const std::string& name);

// The timing.csv header line (no newline).
std::string FrameCsvHeader();
// One timing.csv row (no newline) from the values of every column (FrameColumns() order).
std::string FrameCsvRow(const std::vector<double>& values);
// The values of every column for one report (FrameColumns() order).
std::vector<double> ReadFrameColumns(const FrameReport& report);

}  // namespace esdslam
