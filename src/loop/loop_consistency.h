#pragma once
// ORB-SLAM2's covisibility-consistency test for loop candidates. A candidate's group is the
// candidate plus its connected keyframes. Between consecutive queries (keyframes checked by loop
// closing) the test keeps the groups seen last time, each with a consistency count: a new
// candidate group sharing a keyframe with a kept group continues it (count + 1; each kept group
// is continued at most once per query), one sharing none starts a new group (count 0). A
// candidate whose group reaches `threshold` (ORB-SLAM2: 3, i.e. seen in 4 consecutive queries)
// is "enough consistent". Groups not continued by the current query are dropped. Keyframe ids
// only: no map access, no locking (one owner thread).

#include <set>
#include <utility>
#include <vector>

namespace esdslam {

struct CandidateGroup {
  long candidate = -1;
  std::set<long> keyframes;  // the candidate and its connected keyframes
};

struct ConsistentGroup {
  std::set<long> keyframes;
  int consistency = 0;
};

class LoopConsistency {
 public:
  explicit LoopConsistency(int threshold = 3);

  // Feeds the candidate groups of one query (in candidate order); returns the enough-consistent
  // candidates in that order, each once. An empty input clears the kept groups.
  std::vector<long> Update(const std::vector<CandidateGroup>& candidates);
  // Forgets every kept group (e.g. after a loop was closed).
  void Clear() { groups_.clear(); }
  const std::vector<ConsistentGroup>& groups() const { return groups_; }
  int threshold() const { return threshold_; }

 private:
  int threshold_;
  std::vector<ConsistentGroup> groups_;
};

}  // namespace esdslam
