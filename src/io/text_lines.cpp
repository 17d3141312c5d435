#include "io/text_lines.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>

#include "common/error.h"

namespace esdslam {
namespace {

std::vector<std::string> SplitFields(const std::string& line) {
  std::vector<std::string> fields;
  std::string current;
  for (char c : line) {
    if (c == ' ' || c == '\t' || c == ',' || c == '\r') {
      if (!current.empty()) fields.push_back(std::move(current));
      current.clear();
    } else {
      current.push_back(c);
    }
  }
  if (!current.empty()) fields.push_back(std::move(current));
  return fields;
}

}  // namespace

std::vector<TextLine> ReadTextLines(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, 0, "cannot open file");
  std::vector<TextLine> lines;
  std::string text;
  int line_number = 0;
  while (std::getline(in, text)) {
    ++line_number;
    const auto first = text.find_first_not_of(" \t\r");
    if (first == std::string::npos || text[first] == '#') continue;
    lines.push_back({line_number, SplitFields(text)});
  }
  if (in.bad()) throw InputError(path, line_number, "read error");
  return lines;
}

double ParseFiniteReal(const std::string& field, const std::string& what, const std::string& path, int line) {
  const char* begin = field.c_str();
  char* end = nullptr;
  errno = 0;
  const double value = std::strtod(begin, &end);
  if (end == begin || *end != '\0') {
    throw InputError(path, line, "expected a number for " + what + ", got '" + field + "'");
  }
  if (!std::isfinite(value) || errno == ERANGE) {
    throw InputError(path, line, "expected a finite number for " + what + ", got '" + field + "'");
  }
  return value;
}

void CheckStrictlyIncreasing(const std::vector<double>& timestamps, const std::vector<int>& line_numbers,
                             const std::string& path) {
  for (std::size_t i = 1; i < timestamps.size(); ++i) {
    if (timestamps[i] == timestamps[i - 1]) {
      throw InputError(path, line_numbers[i], fmt::format("duplicate timestamp {:.6f}", timestamps[i]));
    }
    if (timestamps[i] < timestamps[i - 1]) {
      throw InputError(path, line_numbers[i],
                       fmt::format("timestamps not sorted: {:.6f} after {:.6f}", timestamps[i], timestamps[i - 1]));
    }
  }
}

}  // namespace esdslam
