#include "dynamic/keyframe_depth_store.h"

#include <opencv2/imgproc.hpp>

#include "common/error.h"

namespace esdslam {

KeyframeDepthStore::KeyframeDepthStore(int capacity, double scale) : capacity_(capacity), scale_(scale) {
  if (capacity < 0) throw Error("keyframe depth store: capacity must be >= 0");
  if (!(scale > 0 && scale <= 1)) throw Error("keyframe depth store: scale must be in (0, 1]");
}

void KeyframeDepthStore::Add(long id, const cv::Mat& depth_m) {
  if (capacity_ == 0) return;
  if (depth_m.type() != CV_32F || depth_m.empty()) throw Error("keyframe depth store: depth must be CV_32F");
  cv::Mat scaled;
  if (scale_ == 1.0) scaled = depth_m.clone();
  else cv::resize(depth_m, scaled, cv::Size(), scale_, scale_, cv::INTER_NEAREST);
  depths_[id] = {scaled, ++uses_};
  while (static_cast<int>(depths_.size()) > capacity_) {
    auto oldest = depths_.begin();
    for (auto it = depths_.begin(); it != depths_.end(); ++it)
      if (it->second.last_use < oldest->second.last_use) oldest = it;
    depths_.erase(oldest);
  }
}

void KeyframeDepthStore::Erase(long id) { depths_.erase(id); }

cv::Mat KeyframeDepthStore::Find(long id) {
  const auto it = depths_.find(id);
  if (it == depths_.end()) return cv::Mat();
  it->second.last_use = ++uses_;
  return it->second.depth_m;
}

std::size_t KeyframeDepthStore::bytes() const {
  std::size_t total = 0;
  for (const auto& [id, entry] : depths_) total += entry.depth_m.total() * entry.depth_m.elemSize();
  return total;
}

std::vector<long> KeyframeDepthStore::ids() const {
  std::vector<long> out;
  for (const auto& [id, entry] : depths_) out.push_back(id);
  return out;
}

}  // namespace esdslam
