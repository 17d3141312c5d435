#pragma once
// Helpers for the line-based text files of the TUM layout (rgb.txt, depth.txt, groundtruth.txt,
// association files): comment-skipping tokenisation with line numbers and strict number parsing.

#include <string>
#include <vector>

namespace esdslam {

struct TextLine {
  int line_number = 0;              // 1-based
  std::vector<std::string> fields;  // split on spaces, tabs and commas
};

// Reads all non-blank, non-'#' lines. Throws InputError(path, 0, ...) if it cannot be opened.
std::vector<TextLine> ReadTextLines(const std::string& path);

// Parses a finite real number that spans the whole field; throws InputError(path, line, ...)
// naming the field ("timestamp", "tx", ...) otherwise.
double ParseFiniteReal(const std::string& field, const std::string& what, const std::string& path, int line);

// Throws InputError when timestamps[i] <= timestamps[i-1] (unsorted or duplicate).
void CheckStrictlyIncreasing(const std::vector<double>& timestamps, const std::vector<int>& line_numbers,
                             const std::string& path);

}  // namespace esdslam
