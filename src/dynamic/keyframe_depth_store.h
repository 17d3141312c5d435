#pragma once
// Depth images of recent keyframes for the geometry check's static-occlusion veto
// (dynamic/geometry_check.h). Kept at a reduced scale (nearest-neighbour subsampling: no depth
// is mixed across object edges) and for a bounded number of keyframes, so memory stays fixed on
// long sequences: 0.5 scale, CV_32F, VGA = 0.3 MB per keyframe; 100 keyframes = 31 MB. When full,
// the keyframe used least recently (added or found) is dropped; keyframes whose depth was dropped
// simply abstain from the veto. Owned by one thread (tracking).

#include <map>
#include <vector>

#include <opencv2/core.hpp>

namespace esdslam {

class KeyframeDepthStore {
 public:
  // capacity: keyframes kept (0 = none); scale in (0, 1]. Throws Error otherwise.
  KeyframeDepthStore(int capacity, double scale);

  // depth_m: CV_32F metres of keyframe `id` (copied, scaled).
  void Add(long id, const cv::Mat& depth_m);
  void Erase(long id);
  // Scaled depth of keyframe `id` (counts as a use), or an empty Mat.
  cv::Mat Find(long id);
  bool Contains(long id) const { return depths_.count(id) > 0; }

  double scale() const { return scale_; }
  std::size_t size() const { return depths_.size(); }
  std::size_t bytes() const;
  // Ids kept, in increasing order (for pruning by the owner).
  std::vector<long> ids() const;

 private:
  int capacity_;
  double scale_;
  struct Entry {
    cv::Mat depth_m;
    long last_use = 0;
  };
  long uses_ = 0;
  std::map<long, Entry> depths_;
};

}  // namespace esdslam
