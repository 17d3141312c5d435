#include "place/place_recognition.h"

#include <set>

#include "common/error.h"
#include "map/keyframe.h"

namespace esdslam {

void PlaceRecognitionOptions::Check() const {
  if (direct_index_level < 1) throw Error("PlaceRecognitionOptions: direct_index_level must be >= 1");
  if (covisible_neighbours < 1) throw Error("PlaceRecognitionOptions: covisible_neighbours must be >= 1");
  database.Check();
}

PlaceRecognition::PlaceRecognition(std::shared_ptr<const Vocabulary> vocabulary,
                                   const PlaceRecognitionOptions& options)
    : vocabulary_(std::move(vocabulary)), options_(options), database_(options.database) {
  options_.Check();
  if (vocabulary_ == nullptr || vocabulary_->empty()) throw Error("PlaceRecognition: empty vocabulary");
  options_.direct_index_level = std::min(options_.direct_index_level, vocabulary_->levels());
}

ImageBow PlaceRecognition::Compute(const FeatureSet& features) const {
  ImageBow result;
  if (features.descriptors.empty()) return result;
  result.bow = vocabulary_->Transform(features.descriptors, &result.direct_index, options_.direct_index_level);
  return result;
}

void PlaceRecognition::AddKeyFrame(KeyFrame* keyframe) {
  if (Contains(keyframe) || keyframe->is_bad()) return;
  auto bow = std::make_shared<const ImageBow>(Compute(keyframe->features()));
  {
    std::lock_guard<std::mutex> lock(mutex_);
    keyframes_[keyframe->id()] = keyframe;
    bows_[keyframe->id()] = bow;
  }
  database_.Add(keyframe->id(), bow->bow);
}

void PlaceRecognition::AddMissing(const std::vector<KeyFrame*>& keyframes) {
  for (KeyFrame* keyframe : keyframes) AddKeyFrame(keyframe);
}

void PlaceRecognition::EraseKeyFrame(const KeyFrame* keyframe) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    keyframes_.erase(keyframe->id());
    bows_.erase(keyframe->id());
  }
  database_.Erase(keyframe->id());
}

void PlaceRecognition::PurgeBadKeyFrames() {
  std::vector<KeyFrame*> indexed;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& [id, keyframe] : keyframes_) indexed.push_back(keyframe);
  }
  for (KeyFrame* keyframe : indexed)
    if (keyframe->is_bad()) EraseKeyFrame(keyframe);
}

bool PlaceRecognition::Contains(const KeyFrame* keyframe) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return keyframes_.count(keyframe->id()) > 0;
}

std::size_t PlaceRecognition::size() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return keyframes_.size();
}

std::shared_ptr<const ImageBow> PlaceRecognition::KeyFrameBow(const KeyFrame* keyframe) const {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto it = bows_.find(keyframe->id());
  return it == bows_.end() ? nullptr : it->second;
}

// The database calls this with its own mutex held; it takes the store mutex (a leaf) to look the
// keyframe up, releases it, then asks the keyframe for its neighbours.
CovisibleNeighbours PlaceRecognition::NeighbourFunction() const {
  return [this](long id) {
    KeyFrame* keyframe = nullptr;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      const auto it = keyframes_.find(id);
      if (it != keyframes_.end()) keyframe = it->second;
    }
    std::vector<long> ids;
    if (keyframe == nullptr) return ids;
    for (KeyFrame* neighbour : keyframe->BestCovisibleKeyframes(options_.covisible_neighbours))
      if (!neighbour->is_bad()) ids.push_back(neighbour->id());
    return ids;
  };
}

std::vector<KeyFrame*> PlaceRecognition::ToKeyFrames(const std::vector<PlaceCandidate>& candidates) const {
  std::vector<KeyFrame*> keyframes;
  std::lock_guard<std::mutex> lock(mutex_);
  for (const PlaceCandidate& candidate : candidates) {
    const auto it = keyframes_.find(candidate.keyframe_id);
    if (it != keyframes_.end()) keyframes.push_back(it->second);
  }
  return keyframes;
}

std::vector<KeyFrame*> PlaceRecognition::RelocalizationCandidates(const ImageBow& query) {
  PurgeBadKeyFrames();
  std::vector<KeyFrame*> keyframes =
      ToKeyFrames(database_.DetectRelocalizationCandidates(query.bow, NeighbourFunction()));
  std::vector<KeyFrame*> live;
  for (KeyFrame* keyframe : keyframes)
    if (!keyframe->is_bad()) live.push_back(keyframe);
  return live;
}

std::vector<KeyFrame*> PlaceRecognition::LoopCandidates(KeyFrame* query, const std::vector<KeyFrame*>& score_neighbours,
                                                        const std::vector<KeyFrame*>& excluded) {
  PurgeBadKeyFrames();
  const std::shared_ptr<const ImageBow> bow = KeyFrameBow(query);
  if (bow == nullptr) return {};
  std::set<long> excluded_ids{query->id()};
  for (KeyFrame* keyframe : excluded) excluded_ids.insert(keyframe->id());
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (auto it = keyframes_.upper_bound(query->id()); it != keyframes_.end(); ++it) excluded_ids.insert(it->first);
  }
  std::vector<long> neighbour_ids;
  for (KeyFrame* neighbour : score_neighbours) neighbour_ids.push_back(neighbour->id());
  const double min_score = database_.MinScore(bow->bow, neighbour_ids);
  std::vector<KeyFrame*> live;
  for (KeyFrame* keyframe :
       ToKeyFrames(database_.DetectLoopCandidates(bow->bow, excluded_ids, min_score, NeighbourFunction())))
    if (!keyframe->is_bad()) live.push_back(keyframe);
  return live;
}

}  // namespace esdslam
