#pragma once
// Timestamp association as the TUM benchmark tools do it (associate.py): every pair (a, b)
// with |t_a - (t_b + offset)| <= max_difference is a candidate; candidates are taken greedily
// by increasing |dt| (ties: earlier a, then earlier b) so that each element is used at most
// once; the result is sorted by a's time. A tolerance of 1e-9 s is added to max_difference so
// that a difference of exactly max_difference written in decimal (e.g. 1.02 - 1.00) matches.

#include <cstddef>
#include <vector>

namespace esdslam {

struct TimestampMatch {
  std::size_t first = 0;   // index into the first list
  std::size_t second = 0;  // index into the second list
};

// Neither list needs to be sorted. Cost O((n + m) log(n + m) + candidates).
std::vector<TimestampMatch> AssociateTimestamps(const std::vector<double>& first_times,
                                                const std::vector<double>& second_times,
                                                double max_difference, double offset = 0.0);

}  // namespace esdslam
