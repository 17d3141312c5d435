#include "io/associate.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <tuple>

namespace esdslam {
namespace {

// Absolute tolerance so that decimal differences of exactly max_difference match.
constexpr double kToleranceS = 1e-9;

struct Candidate {
  double abs_dt;
  double first_time;
  double second_time;
  std::size_t first;
  std::size_t second;
};

std::vector<std::size_t> SortedOrder(const std::vector<double>& times) {
  std::vector<std::size_t> order(times.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return times[a] < times[b]; });
  return order;
}

// All pairs within the window, found by a binary search per element of the first list.
std::vector<Candidate> CollectCandidates(const std::vector<double>& first_times,
                                         const std::vector<double>& second_times, double max_difference,
                                         double offset) {
  const std::vector<std::size_t> second_order = SortedOrder(second_times);
  std::vector<double> shifted_second(second_order.size());
  for (std::size_t k = 0; k < second_order.size(); ++k) shifted_second[k] = second_times[second_order[k]] + offset;
  const double window = max_difference + kToleranceS;
  std::vector<Candidate> candidates;
  for (std::size_t i = 0; i < first_times.size(); ++i) {
    const double t = first_times[i];
    auto it = std::lower_bound(shifted_second.begin(), shifted_second.end(), t - window);
    for (; it != shifted_second.end() && *it <= t + window; ++it) {
      const std::size_t k = static_cast<std::size_t>(it - shifted_second.begin());
      const double abs_dt = std::abs(t - *it);
      if (abs_dt <= window) candidates.push_back({abs_dt, t, *it, i, second_order[k]});
    }
  }
  return candidates;
}

}  // namespace

std::vector<TimestampMatch> AssociateTimestamps(const std::vector<double>& first_times,
                                                const std::vector<double>& second_times, double max_difference,
                                                double offset) {
  std::vector<Candidate> candidates = CollectCandidates(first_times, second_times, max_difference, offset);
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
    return std::tie(a.abs_dt, a.first_time, a.second_time, a.first, a.second) <
           std::tie(b.abs_dt, b.first_time, b.second_time, b.first, b.second);
  });
  std::vector<bool> first_used(first_times.size(), false), second_used(second_times.size(), false);
  std::vector<TimestampMatch> matches;
  for (const Candidate& c : candidates) {
    if (first_used[c.first] || second_used[c.second]) continue;
    first_used[c.first] = second_used[c.second] = true;
    matches.push_back({c.first, c.second});
  }
  std::sort(matches.begin(), matches.end(), [&](const TimestampMatch& a, const TimestampMatch& b) {
    return first_times[a.first] != first_times[b.first] ? first_times[a.first] < first_times[b.first]
                                                        : a.first < b.first;
  });
  return matches;
}

}  // namespace esdslam
