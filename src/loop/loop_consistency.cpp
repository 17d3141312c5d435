#include "loop/loop_consistency.h"

#include <algorithm>

#include "common/error.h"

namespace esdslam {
namespace {

bool ShareAny(const std::set<long>& a, const std::set<long>& b) {
  const std::set<long>& smaller = a.size() < b.size() ? a : b;
  const std::set<long>& larger = a.size() < b.size() ? b : a;
  return std::any_of(smaller.begin(), smaller.end(), [&](long id) { return larger.count(id) > 0; });
}

}  // namespace

LoopConsistency::LoopConsistency(int threshold) : threshold_(threshold) {
  if (threshold_ < 1) throw Error("LoopConsistency: threshold must be >= 1");
}

std::vector<long> LoopConsistency::Update(const std::vector<CandidateGroup>& candidates) {
  std::vector<long> enough;
  std::vector<ConsistentGroup> current;
  std::vector<bool> continued(groups_.size(), false);
  for (const CandidateGroup& candidate : candidates) {
    bool consistent_with_some = false;
    bool is_enough = false;
    for (std::size_t g = 0; g < groups_.size(); ++g) {
      if (!ShareAny(candidate.keyframes, groups_[g].keyframes)) continue;
      consistent_with_some = true;
      const int consistency = groups_[g].consistency + 1;
      if (!continued[g]) {
        current.push_back({candidate.keyframes, consistency});
        continued[g] = true;
      }
      if (consistency >= threshold_ && !is_enough) {
        enough.push_back(candidate.candidate);
        is_enough = true;
      }
    }
    if (!consistent_with_some) current.push_back({candidate.keyframes, 0});
  }
  groups_ = std::move(current);
  return enough;
}

}  // namespace esdslam
