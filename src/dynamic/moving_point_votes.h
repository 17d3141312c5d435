#pragma once
// Which map points moved: per-point votes from the geometry check over consecutive frames.
//
// Each frame a point can get evidence that it moved (the check now sees through it, or it was
// matched to a keypoint on a region found moving) or be measured where it should be. Evidence
// in `frames_to_cull` consecutive frames in which the point was tested marks it for culling; a
// consistent measurement resets its count; frames in which it was not tested leave it unchanged.
// One frame of evidence is not enough: a static point on a depth edge can look "seen through"
// when its projection lands a pixel off the edge, but not frame after frame. Counts untouched
// for `forget_after_frames` frames are dropped (bounded memory).

#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace esdslam {

class MovingPointVotes {
 public:
  // Throws Error unless frames_to_cull >= 1 and forget_after_frames >= 1.
  explicit MovingPointVotes(int frames_to_cull = 3, int forget_after_frames = 60);

  // During a frame (several calls per point are counted once; evidence wins over consistency).
  void Evidence(long point_id);
  void Consistent(long point_id);
  // Ends the frame; returns the points whose evidence reached frames_to_cull (in increasing id
  // order; their counts are removed).
  std::vector<long> EndFrame();

  int count(long point_id) const;  // current consecutive evidence count
  std::size_t size() const { return counts_.size(); }

 private:
  struct Count {
    int frames = 0;
    long last_frame = 0;
  };
  int frames_to_cull_;
  int forget_after_frames_;
  long frame_ = 0;
  std::unordered_set<long> evidence_, consistent_;  // this frame
  std::unordered_map<long, Count> counts_;
};

}  // namespace esdslam
