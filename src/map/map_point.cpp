#include "map/map_point.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "feature/descriptor.h"
#include "map/keyframe.h"
#include "map/map.h"

namespace esdslam {

bool KeyFrameIdLess::operator()(const KeyFrame* a, const KeyFrame* b) const { return a->id() < b->id(); }
bool MapPointIdLess::operator()(const MapPoint* a, const MapPoint* b) const { return a->id() < b->id(); }

MapPoint::MapPoint(long id, const Vec3& position_world, KeyFrame* reference_keyframe, Map* map)
    : id_(id),
      first_keyframe_id_(reference_keyframe ? reference_keyframe->id() : -1),
      map_(map),
      position_(position_world),
      reference_keyframe_(reference_keyframe) {}

Vec3 MapPoint::position() const {
  std::lock_guard<std::mutex> lock(mutex_position_);
  return position_;
}
void MapPoint::set_position(const Vec3& position_world) {
  std::lock_guard<std::mutex> lock(mutex_position_);
  position_ = position_world;
}
Vec3 MapPoint::normal() const {
  std::lock_guard<std::mutex> lock(mutex_position_);
  return normal_;
}
double MapPoint::min_distance() const {
  std::lock_guard<std::mutex> lock(mutex_position_);
  return 0.8 * min_distance_;
}
double MapPoint::max_distance() const {
  std::lock_guard<std::mutex> lock(mutex_position_);
  return 1.2 * max_distance_;
}

int MapPoint::PredictLevel(double distance, int num_levels, double log_scale_factor) const {
  double ratio;
  {
    std::lock_guard<std::mutex> lock(mutex_position_);
    ratio = max_distance_ / std::max(distance, 1e-9);
  }
  const int level = static_cast<int>(std::ceil(std::log(ratio) / log_scale_factor));
  return std::clamp(level, 0, num_levels - 1);
}

std::map<KeyFrame*, int, KeyFrameIdLess> MapPoint::observations() const {
  std::lock_guard<std::mutex> lock(mutex_observations_);
  return observations_;
}

std::vector<KeyFrame*> MapPoint::observing_keyframes() const {
  std::lock_guard<std::mutex> lock(mutex_observations_);
  std::vector<KeyFrame*> keyframes;
  keyframes.reserve(observations_.size());
  for (const auto& observation : observations_) keyframes.push_back(observation.first);
  return keyframes;
}

void MapPoint::AddObservation(KeyFrame* keyframe, int keypoint_index, bool with_depth) {
  std::lock_guard<std::mutex> lock(mutex_observations_);
  if (observations_.count(keyframe)) return;
  observations_[keyframe] = keypoint_index;
  num_observations_ += with_depth ? 2 : 1;
}

void MapPoint::EraseObservation(KeyFrame* keyframe) {
  bool now_bad = false;
  {
    std::lock_guard<std::mutex> lock(mutex_observations_);
    auto it = observations_.find(keyframe);
    if (it == observations_.end()) return;
    num_observations_ -= keyframe->features().has_depth(it->second) ? 2 : 1;
    observations_.erase(it);
    if (reference_keyframe_ == keyframe && !observations_.empty())
      reference_keyframe_ = observations_.begin()->first;
    now_bad = num_observations_ <= 2;
  }
  if (now_bad) SetBad();
}

int MapPoint::KeypointIndexIn(const KeyFrame* keyframe) const {
  std::lock_guard<std::mutex> lock(mutex_observations_);
  auto it = observations_.find(const_cast<KeyFrame*>(keyframe));
  return it == observations_.end() ? -1 : it->second;
}

int MapPoint::num_observations() const {
  std::lock_guard<std::mutex> lock(mutex_observations_);
  return num_observations_;
}
int MapPoint::num_observing_keyframes() const {
  std::lock_guard<std::mutex> lock(mutex_observations_);
  return static_cast<int>(observations_.size());
}
KeyFrame* MapPoint::reference_keyframe() const {
  std::lock_guard<std::mutex> lock(mutex_observations_);
  return reference_keyframe_;
}
cv::Mat MapPoint::descriptor() const {
  std::lock_guard<std::mutex> lock(mutex_observations_);
  return descriptor_.clone();
}

void MapPoint::set_descriptor(const cv::Mat& descriptor) {
  std::lock_guard<std::mutex> lock(mutex_observations_);
  descriptor_ = descriptor.clone();
}

void MapPoint::ComputeDistinctiveDescriptor() {
  std::vector<const unsigned char*> candidates;
  for (const auto& [keyframe, index] : observations()) {
    if (keyframe->is_bad()) continue;
    candidates.push_back(keyframe->features().descriptor(index));
  }
  if (candidates.empty()) return;
  const int n = static_cast<int>(candidates.size());
  std::vector<std::vector<int>> distances(n, std::vector<int>(n, 0));
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) distances[i][j] = distances[j][i] = DescriptorDistance(candidates[i], candidates[j]);
  int best_median = std::numeric_limits<int>::max(), best = 0;
  for (int i = 0; i < n; ++i) {
    std::vector<int> row = distances[i];
    std::nth_element(row.begin(), row.begin() + (n - 1) / 2, row.end());
    const int median = row[(n - 1) / 2];
    if (median < best_median) best_median = median, best = i;
  }
  cv::Mat chosen(1, 32, CV_8U);
  std::copy(candidates[best], candidates[best] + 32, chosen.ptr<unsigned char>(0));
  std::lock_guard<std::mutex> lock(mutex_observations_);
  descriptor_ = chosen;
}

void MapPoint::UpdateNormalAndDepth() {
  const auto observing = observations();
  KeyFrame* reference = reference_keyframe();
  if (observing.empty() || reference == nullptr || is_bad()) return;
  const Vec3 position_world = position();
  Vec3 normal_sum = Vec3::Zero();
  for (const auto& [keyframe, index] : observing) {
    (void)index;
    normal_sum += (position_world - keyframe->camera_center()).normalized();
  }
  const double distance = (position_world - reference->camera_center()).norm();
  const int ref_index = KeypointIndexIn(reference);
  if (ref_index < 0) return;
  const auto& pyramid = reference->rig().pyramid;
  const int level = reference->features().level(ref_index);
  std::lock_guard<std::mutex> lock(mutex_position_);
  max_distance_ = distance * pyramid.scale_factors[level];
  min_distance_ = max_distance_ / pyramid.scale_factors[pyramid.num_levels - 1];
  normal_ = normal_sum.normalized();
}

void MapPoint::SetBad() {
  std::map<KeyFrame*, int, KeyFrameIdLess> observing;
  {
    std::lock_guard<std::mutex> lock(mutex_observations_);
    if (bad_) return;
    bad_ = true;
    observing.swap(observations_);
    num_observations_ = 0;
  }
  for (const auto& [keyframe, index] : observing) keyframe->EraseMapPoint(index);
  map_->EraseMapPoint(this);
}

bool MapPoint::is_bad() const {
  std::lock_guard<std::mutex> lock(mutex_observations_);
  return bad_;
}

void MapPoint::Replace(MapPoint* other) {
  if (other == this || other == nullptr) return;
  std::map<KeyFrame*, int, KeyFrameIdLess> observing;
  int visible, found;
  {
    std::lock_guard<std::mutex> lock(mutex_observations_);
    if (bad_) return;
    observing.swap(observations_);
    num_observations_ = 0;
    bad_ = true;
    replaced_by_ = other;
    visible = visible_;
    found = found_;
  }
  for (const auto& [keyframe, index] : observing) {
    if (!other->IsObservedBy(keyframe)) {
      keyframe->ReplaceMapPoint(index, other);
      other->AddObservation(keyframe, index, keyframe->features().has_depth(index));
    } else {
      keyframe->EraseMapPoint(index);
    }
  }
  other->IncreaseFound(found);
  other->IncreaseVisible(visible);
  other->ComputeDistinctiveDescriptor();
  map_->EraseMapPoint(this);
}

MapPoint* MapPoint::replaced_by() const {
  const MapPoint* current = this;
  for (int hops = 0; hops < 64; ++hops) {
    MapPoint* next;
    {
      std::lock_guard<std::mutex> lock(current->mutex_observations_);
      next = current->replaced_by_;
    }
    if (next == nullptr) break;
    current = next;
  }
  return const_cast<MapPoint*>(current);
}

}  // namespace esdslam
