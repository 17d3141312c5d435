#pragma once
// Choosing the reference keyframes of the multi-view geometry check: the (up to 5) keyframes
// that overlap most with the current frame.

#include <vector>

#include "camera/pinhole_camera.h"
#include "common/geometry.h"

namespace esdslam {

// From per-keyframe counts of points shared with the current frame (e.g. covisibility weights):
// indices of the `max_count` largest counts, largest first (ties: lower index first); keyframes
// sharing nothing are never chosen.
std::vector<int> SelectReferenceKeyframes(const std::vector<int>& shared_point_counts, int max_count = 5);

// The counts with those of keyframes younger than `min_age_s` (timestamp after frame_time_s -
// min_age_s) set to 0, when an old enough keyframe shares points; unchanged when none does (the
// first keyframes of a run). keyframe_times_s: one per count (s, the frames' clock).
std::vector<int> WithoutYoungKeyframes(std::vector<int> shared_point_counts, const std::vector<double>& keyframe_times_s,
                                       double frame_time_s, double min_age_s);

// Without correspondences: a 16 x 12 grid of each keyframe's pixels, back-projected at
// `scene_depth_m`, is projected into the current camera; the score is the number of grid points
// that land in the image with a parallax angle <= max_parallax_deg. Returns the `max_count`
// best-scoring keyframes (score > 0), best first.
std::vector<int> SelectKeyframesByViewOverlap(const PinholeCamera& camera, const Rigid3& cam_from_world,
                                              const std::vector<Rigid3>& keyframe_world_from_cams,
                                              double scene_depth_m, int max_count = 5,
                                              double max_parallax_deg = 30.0);

}  // namespace esdslam
