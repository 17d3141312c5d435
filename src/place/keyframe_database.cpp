#include "place/keyframe_database.h"

#include <algorithm>

#include "common/error.h"

namespace esdslam {

void KeyFrameDatabaseOptions::Check() const {
  if (!(min_common_words_ratio > 0.0 && min_common_words_ratio <= 1.0))
    throw Error("keyframe database: min_common_words_ratio must be in (0, 1]");
  if (!(group_score_ratio > 0.0 && group_score_ratio <= 1.0))
    throw Error("keyframe database: group_score_ratio must be in (0, 1]");
}

KeyFrameDatabase::KeyFrameDatabase(const KeyFrameDatabaseOptions& options) : options_(options) { options_.Check(); }

void KeyFrameDatabase::Add(long keyframe_id, const BowVector& bow) {
  std::lock_guard<std::mutex> lock(mutex_);
  EraseLocked(keyframe_id);
  bows_[keyframe_id] = bow;
  for (const BowEntry& entry : bow) inverted_index_[entry.word].push_back(keyframe_id);
}

void KeyFrameDatabase::Erase(long keyframe_id) {
  std::lock_guard<std::mutex> lock(mutex_);
  EraseLocked(keyframe_id);
}

void KeyFrameDatabase::EraseLocked(long keyframe_id) {
  const auto it = bows_.find(keyframe_id);
  if (it == bows_.end()) return;
  for (const BowEntry& entry : it->second) {
    auto& ids = inverted_index_[entry.word];
    ids.erase(std::remove(ids.begin(), ids.end(), keyframe_id), ids.end());
    if (ids.empty()) inverted_index_.erase(entry.word);
  }
  bows_.erase(it);
}

void KeyFrameDatabase::Clear() {
  std::lock_guard<std::mutex> lock(mutex_);
  inverted_index_.clear();
  bows_.clear();
}

bool KeyFrameDatabase::Contains(long keyframe_id) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return bows_.count(keyframe_id) > 0;
}

std::size_t KeyFrameDatabase::size() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return bows_.size();
}

BowVector KeyFrameDatabase::bow(long keyframe_id) const {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto it = bows_.find(keyframe_id);
  return it == bows_.end() ? BowVector() : it->second;
}

double KeyFrameDatabase::MinScore(const BowVector& query, const std::vector<long>& keyframe_ids) const {
  std::lock_guard<std::mutex> lock(mutex_);
  double min_score = 1.0;
  for (const long id : keyframe_ids) {
    const auto it = bows_.find(id);
    if (it != bows_.end()) min_score = std::min(min_score, L1Score(query, it->second));
  }
  return min_score;
}

std::map<long, int> KeyFrameDatabase::CountCommonWords(const BowVector& query, const std::set<long>& excluded) const {
  std::map<long, int> shared;
  for (const BowEntry& entry : query) {
    const auto it = inverted_index_.find(entry.word);
    if (it == inverted_index_.end()) continue;
    for (const long id : it->second) {
      if (excluded.count(id) == 0) ++shared[id];
    }
  }
  return shared;
}

std::vector<PlaceCandidate> KeyFrameDatabase::Detect(const BowVector& query, const std::set<long>& excluded,
                                                     double min_score, const CovisibleNeighbours& neighbours) const {
  // 1. Keyframes sharing words, filtered by number of common words, then by score.
  const std::map<long, int> shared = CountCommonWords(query, excluded);
  if (shared.empty()) return {};
  int max_common = 0;
  for (const auto& [id, common] : shared) max_common = std::max(max_common, common);
  const double min_common = options_.min_common_words_ratio * max_common;
  // Scores of every keyframe with enough common words; groups start only from those >= min_score
  // but accumulate every scored neighbour (as ORB-SLAM2 does).
  std::map<long, double> scored;
  for (const auto& [id, common] : shared) {
    if (common > min_common) scored[id] = L1Score(query, bows_.at(id));
  }

  // 2. Accumulate over covisibility groups: a candidate plus its neighbours that were scored.
  std::vector<PlaceCandidate> groups;
  double best_accumulated = 0.0;
  for (const auto& [id, score] : scored) {
    if (score < min_score) continue;
    PlaceCandidate group{id, score, score};
    if (neighbours) {
      for (const long neighbour : neighbours(id)) {
        const auto it = scored.find(neighbour);
        if (neighbour == id || it == scored.end()) continue;
        group.accumulated_score += it->second;
        if (it->second > group.score) group = {neighbour, it->second, group.accumulated_score};
      }
    }
    best_accumulated = std::max(best_accumulated, group.accumulated_score);
    groups.push_back(group);
  }
  if (groups.empty()) return {};

  // 3. Best keyframe of every group scoring above the ratio of the best group, unique ids.
  std::sort(groups.begin(), groups.end(), [](const PlaceCandidate& a, const PlaceCandidate& b) {
    return a.accumulated_score != b.accumulated_score ? a.accumulated_score > b.accumulated_score
                                                      : a.keyframe_id < b.keyframe_id;
  });
  std::vector<PlaceCandidate> candidates;
  std::set<long> taken;
  for (const PlaceCandidate& group : groups) {
    if (group.accumulated_score <= options_.group_score_ratio * best_accumulated) continue;
    if (taken.insert(group.keyframe_id).second) candidates.push_back(group);
  }
  return candidates;
}

std::vector<PlaceCandidate> KeyFrameDatabase::DetectLoopCandidates(const BowVector& query, const std::set<long>& excluded,
                                                                   double min_score,
                                                                   const CovisibleNeighbours& neighbours) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return Detect(query, excluded, min_score, neighbours);
}

std::vector<PlaceCandidate> KeyFrameDatabase::DetectRelocalizationCandidates(const BowVector& query,
                                                                             const CovisibleNeighbours& neighbours) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return Detect(query, {}, 0.0, neighbours);
}

}  // namespace esdslam
