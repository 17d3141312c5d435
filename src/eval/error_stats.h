#pragma once
// Summary statistics of a list of non-negative errors, with the TUM benchmark's definitions:
// rmse = sqrt(mean(e^2)), std = population standard deviation (numpy.std), median = numpy.median
// (mean of the two middle values for an even count).

#include <cstddef>
#include <vector>

namespace esdslam {

struct ErrorStats {
  double rmse = 0, mean = 0, median = 0, std = 0, min = 0, max = 0;
  std::size_t count = 0;
};

// Throws Error for an empty list.
ErrorStats ComputeErrorStats(const std::vector<double>& errors);

}  // namespace esdslam
