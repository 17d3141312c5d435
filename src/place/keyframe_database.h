#pragma once
// Keyframe database for place recognition (ORB-SLAM2's KeyFrameDatabase, map-agnostic):
// an inverted index word -> keyframes whose BoW vector contains the word. Keyframes are ids
// with their BoW vectors; the covisibility graph stays with the caller, who passes, per
// query, the keyframes to exclude and a function giving a keyframe's best covisible neighbours.
// Thread-safe: every public method locks the database's mutex (the callbacks are called with it
// held, so they must not call back into the database).

#include <functional>
#include <map>
#include <mutex>
#include <set>
#include <unordered_map>
#include <vector>

#include "place/bow_vector.h"

namespace esdslam {

// The caller's covisibility graph: up to N best covisible keyframe ids of a keyframe (ORB-SLAM2
// uses the 10 best), in any order. Ids unknown to the database are ignored.
using CovisibleNeighbours = std::function<std::vector<long>(long keyframe_id)>;

struct PlaceCandidate {
  long keyframe_id = -1;
  double score = 0.0;              // BoW similarity to the query
  double accumulated_score = 0.0;  // summed over its covisibility group
};

struct KeyFrameDatabaseOptions {
  double min_common_words_ratio = 0.8;  // candidates share >= 0.8 x the best candidate's common words
  double group_score_ratio = 0.75;      // keep groups with accumulated score > 0.75 x the best

  void Check() const;
};

class KeyFrameDatabase {
 public:
  explicit KeyFrameDatabase(const KeyFrameDatabaseOptions& options = {});

  // Adds (or replaces) a keyframe.
  void Add(long keyframe_id, const BowVector& bow);
  // Removes a keyframe; no-op when absent.
  void Erase(long keyframe_id);
  void Clear();
  bool Contains(long keyframe_id) const;
  std::size_t size() const;
  // A copy of a keyframe's BoW vector (empty when absent).
  BowVector bow(long keyframe_id) const;

  // Lowest BoW score between `bow` and the listed keyframes (ids absent from the database are
  // skipped); 1 when none is present. ORB-SLAM2's minimum score for loop candidates, computed
  // over the query keyframe's covisible neighbours.
  double MinScore(const BowVector& bow, const std::vector<long>& keyframe_ids) const;

  // Loop candidates for a keyframe: keyframes sharing words with it, not in `excluded` (the
  // query itself and its covisible neighbours), with score >= min_score; scores accumulated over
  // each candidate's covisibility group, returning the best keyframe of each group whose
  // accumulated score exceeds group_score_ratio x the best group's. Sorted by decreasing
  // accumulated score, ids unique.
  std::vector<PlaceCandidate> DetectLoopCandidates(const BowVector& query, const std::set<long>& excluded,
                                                   double min_score, const CovisibleNeighbours& neighbours) const;
  // Relocalization candidates for a frame: the same without exclusion or minimum score.
  std::vector<PlaceCandidate> DetectRelocalizationCandidates(const BowVector& query,
                                                             const CovisibleNeighbours& neighbours) const;

 private:
  // Keyframe id -> number of words shared with the query.
  std::map<long, int> CountCommonWords(const BowVector& query, const std::set<long>& excluded) const;
  std::vector<PlaceCandidate> Detect(const BowVector& query, const std::set<long>& excluded, double min_score,
                                     const CovisibleNeighbours& neighbours) const;

  void EraseLocked(long keyframe_id);

  KeyFrameDatabaseOptions options_;
  mutable std::mutex mutex_;
  std::unordered_map<WordId, std::vector<long>> inverted_index_;  // word -> keyframe ids
  std::map<long, BowVector> bows_;
};

}  // namespace esdslam
