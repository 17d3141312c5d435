#include "dynamic/moving_point_votes.h"

#include <algorithm>

#include "common/error.h"

namespace esdslam {

MovingPointVotes::MovingPointVotes(int frames_to_cull, int forget_after_frames)
    : frames_to_cull_(frames_to_cull), forget_after_frames_(forget_after_frames) {
  if (frames_to_cull < 1 || forget_after_frames < 1)
    throw Error("moving point votes: frames_to_cull and forget_after_frames must be >= 1");
}

void MovingPointVotes::Evidence(long point_id) { evidence_.insert(point_id); }
void MovingPointVotes::Consistent(long point_id) { consistent_.insert(point_id); }

int MovingPointVotes::count(long point_id) const {
  const auto it = counts_.find(point_id);
  return it == counts_.end() ? 0 : it->second.frames;
}

std::vector<long> MovingPointVotes::EndFrame() {
  ++frame_;
  std::vector<long> reached;
  for (const long id : consistent_) {
    if (!evidence_.count(id)) counts_.erase(id);
  }
  for (const long id : evidence_) {
    Count& count = counts_[id];
    ++count.frames;
    count.last_frame = frame_;
    if (count.frames >= frames_to_cull_) reached.push_back(id);
  }
  for (const long id : reached) counts_.erase(id);
  evidence_.clear();
  consistent_.clear();
  if (frame_ % forget_after_frames_ == 0) {
    for (auto it = counts_.begin(); it != counts_.end();) {
      it = frame_ - it->second.last_frame >= forget_after_frames_ ? counts_.erase(it) : std::next(it);
    }
  }
  std::sort(reached.begin(), reached.end());
  return reached;
}

}  // namespace esdslam
