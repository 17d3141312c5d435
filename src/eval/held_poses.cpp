#include "eval/held_poses.h"

#include <cmath>

namespace esdslam {

HeldTrajectory HoldPosesAtFrames(const std::vector<StampedPose>& estimate, const std::vector<double>& frame_times_s,
                                 double match_s) {
  HeldTrajectory held;
  held.frames = frame_times_s.size();
  std::size_t next = 0;               // first estimate pose not yet at or before the frame
  const StampedPose* newest = nullptr;  // the newest estimate pose at or before the frame
  for (const double t : frame_times_s) {
    while (next < estimate.size() && estimate[next].timestamp <= t + match_s) newest = &estimate[next++];
    if (newest == nullptr) {
      ++held.before_first;
      continue;
    }
    if (std::abs(newest->timestamp - t) <= match_s) ++held.with_pose;
    else ++held.held;
    held.poses.push_back({t, newest->world_from_cam});
  }
  return held;
}

}  // namespace esdslam
