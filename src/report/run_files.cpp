#include "report/run_files.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/error.h"

namespace esdslam {
namespace fs = std::filesystem;
namespace {

std::vector<std::string> SplitComma(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream in(line);
  std::string cell;
  while (std::getline(in, cell, ',')) cells.push_back(cell);
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

std::string StripCarriageReturn(std::string line) {
  if (!line.empty() && line.back() == '\r') line.pop_back();
  return line;
}

std::size_t ColumnIndex(const TimingTable& table, const std::string& name) {
  const auto it = std::find(table.columns.begin(), table.columns.end(), name);
  if (it == table.columns.end()) throw Error("timing.csv has no column '" + name + "'");
  return static_cast<std::size_t>(it - table.columns.begin());
}

// The whole cell as a finite number, else NaN.
double ParseCell(const std::string& cell) {
  if (cell.empty()) return NAN;
  char* end = nullptr;
  const double value = std::strtod(cell.c_str(), &end);
  return (end == cell.c_str() + cell.size() && std::isfinite(value)) ? value : NAN;
}

}  // namespace

bool TimingTable::Has(const std::string& name) const {
  return std::find(columns.begin(), columns.end(), name) != columns.end();
}

std::vector<double> TimingTable::Numbers(const std::string& name) const {
  const std::size_t column = ColumnIndex(*this, name);
  std::vector<double> values;
  values.reserve(rows.size());
  for (const auto& row : rows) values.push_back(ParseCell(row[column]));
  return values;
}

std::vector<std::string> TimingTable::Text(const std::string& name) const {
  const std::size_t column = ColumnIndex(*this, name);
  std::vector<std::string> values;
  values.reserve(rows.size());
  for (const auto& row : rows) values.push_back(row[column]);
  return values;
}

TimingTable ReadTimingCsv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, 0, "cannot open (expected the run's timing.csv)");
  TimingTable table;
  std::string line;
  if (!std::getline(in, line)) throw InputError(path, 1, "empty file: expected a header line");
  table.columns = SplitComma(StripCarriageReturn(line));
  int number = 1;
  while (std::getline(in, line)) {
    ++number;
    line = StripCarriageReturn(line);
    if (line.empty()) continue;
    std::vector<std::string> cells = SplitComma(line);
    if (cells.size() != table.columns.size())
      throw InputError(path, number,
                       fmt::format("{} cells, expected {} (the header's columns)", cells.size(), table.columns.size()));
    table.rows.push_back(std::move(cells));
  }
  return table;
}

std::vector<std::pair<std::string, std::string>> ReadFlatYaml(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, 0, "cannot open");
  std::vector<std::pair<std::string, std::string>> entries;
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    line = StripCarriageReturn(line);
    if (line.empty() || line[0] == '%' || line[0] == '#' || line == "---") continue;
    const std::size_t colon = line.find(": ");
    if (colon == std::string::npos) throw InputError(path, number, "expected 'key: value'");
    entries.emplace_back(line.substr(0, colon), line.substr(colon + 2));
  }
  return entries;
}

std::vector<DebugPicture> ListDebugPictures(const std::string& dir) {
  std::vector<DebugPicture> pictures;
  std::error_code error;
  if (dir.empty() || !fs::is_directory(dir, error)) return pictures;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (!entry.is_regular_file() || entry.path().extension() != ".png") continue;
    const double timestamp = ParseCell(entry.path().stem().string());
    if (std::isfinite(timestamp)) pictures.push_back({timestamp, entry.path().string()});
  }
  std::sort(pictures.begin(), pictures.end(),
            [](const DebugPicture& a, const DebugPicture& b) { return a.timestamp < b.timestamp; });
  return pictures;
}

RunFiles ReadRunFiles(const std::string& out_dir, const std::string& debug_dir) {
  const fs::path out(out_dir);
  RunFiles files;
  files.out_dir = out_dir;
  files.trajectory = ReadTumTrajectory((out / "trajectory.txt").string());
  if (fs::is_regular_file(out / "keyframes.txt")) files.keyframes = ReadTumTrajectory((out / "keyframes.txt").string());
  files.timing = ReadTimingCsv((out / "timing.csv").string());
  if (fs::is_regular_file(out / "settings_used.yaml")) files.settings = ReadFlatYaml((out / "settings_used.yaml").string());
  files.debug_pictures = ListDebugPictures(debug_dir);
  return files;
}

}  // namespace esdslam
