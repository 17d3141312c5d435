#pragma once
// The trajectory a live consumer of the SLAM system had at every frame: ATE "over all frames".
// A run's trajectory has poses only for the frames it tracked; frames it dropped (sensor-clock
// playback, a camera) or lost have none, and the TUM ATE simply leaves them out, so a run that
// skipped half the frames looks as good as one that tracked them all. Holding the newest pose
// at each frame that has none (what a robot reading the system's pose at that moment would
// use) puts every frame into the ATE: a frame without a pose costs the motion since the last one.

#include <cstddef>
#include <vector>

#include "io/trajectory_io.h"

namespace esdslam {

struct HeldTrajectory {
  std::vector<StampedPose> poses;  // one per frame from the first pose on, at the frame's time
  std::size_t frames = 0;          // frames given
  std::size_t with_pose = 0;       // of those, with their own pose in the estimate
  std::size_t held = 0;            // given the newest earlier pose
  std::size_t before_first = 0;    // before the estimate's first pose: none to hold, left out
};

// frame_times_s: every frame's time, increasing (a sequence's frames). A frame has its own pose
// when the estimate has one within match_s of its time (trajectory files keep 6 decimals).
// Estimate poses at no listed frame are not used.
HeldTrajectory HoldPosesAtFrames(const std::vector<StampedPose>& estimate, const std::vector<double>& frame_times_s,
                                 double match_s = 1e-4);

}  // namespace esdslam
