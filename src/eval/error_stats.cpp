#include "eval/error_stats.h"

#include <algorithm>
#include <cmath>

#include "common/error.h"

namespace esdslam {

ErrorStats ComputeErrorStats(const std::vector<double>& errors) {
  if (errors.empty()) throw Error("cannot summarise an empty list of errors");
  const double n = static_cast<double>(errors.size());
  ErrorStats stats;
  stats.count = errors.size();
  double sum = 0, sum_squares = 0;
  for (double e : errors) {
    sum += e;
    sum_squares += e * e;
  }
  stats.mean = sum / n;
  stats.rmse = std::sqrt(sum_squares / n);
  double deviation_squares = 0;
  for (double e : errors) deviation_squares += (e - stats.mean) * (e - stats.mean);
  stats.std = std::sqrt(deviation_squares / n);  // population std, as numpy.std
  std::vector<double> sorted = errors;
  std::sort(sorted.begin(), sorted.end());
  const std::size_t mid = sorted.size() / 2;
  stats.median = sorted.size() % 2 == 1 ? sorted[mid] : 0.5 * (sorted[mid - 1] + sorted[mid]);
  stats.min = sorted.front();
  stats.max = sorted.back();
  return stats;
}

}  // namespace esdslam
