#pragma once
// Error reporting for the library. The library never terminates the process: every failure
// is an esdslam::Error carrying where it happened (file and, for text inputs, line) and what
// was expected. The CLI turns it into a message and a non-zero exit status.

#include <stdexcept>
#include <string>

#include <fmt/format.h>

namespace esdslam {

class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

// An error in an input file. `line` is 1-based; 0 means "the file as a whole".
class InputError : public Error {
 public:
  InputError(const std::string& file, int line, const std::string& what)
      : Error(line > 0 ? fmt::format("{}:{}: {}", file, line, what) : fmt::format("{}: {}", file, what)),
        file_(file),
        line_(line) {}
  const std::string& file() const { return file_; }
  int line() const { return line_; }

 private:
  std::string file_;
  int line_;
};

}  // namespace esdslam
