#pragma once
// Descriptor matching between a Frame and map points (ORB-SLAM2's ORBmatcher searches used by
// tracking). Matches are written into Frame::map_points; dynamic keypoints are never matched.

#include <vector>

#include "tracking/frame.h"

namespace esdslam {

// Keeps only matches whose rotation change (keypoint angle difference) falls in the three most
// populated 30-degree histogram bins (the 2nd/3rd only with >= 10% of the largest). `angle_pairs`
// holds (query angle - train angle, match id); returns the ids to discard.
std::vector<int> RotationInconsistentMatches(const std::vector<std::pair<float, int>>& angle_pairs);

// Projects the last frame's (non-outlier) map points with current.cam_from_world and matches them
// within `radius_px` * scale of the last keypoint's level (RGB-D: also checks the virtual right
// coordinate). Returns the number of new matches.
int SearchByProjection(Frame* current, const Frame& last, double radius_px);

// Matches local map points (flagged in view by Frame::IsInFrustum) not yet matched in the frame.
// Window: radius_factor * (2.5 or 4 by viewing angle) * scale of the predicted level.
int SearchLocalPoints(Frame* frame, const std::vector<MapPoint*>& candidates, double radius_factor);

// Brute-force matching of the keyframe's map points to the frame's keypoints (mutual best,
// distance <= TH_LOW-ish threshold, ratio test 0.7, rotation consistency).
int SearchKeyFrameBruteForce(const KeyFrame& keyframe, Frame* frame);

}  // namespace esdslam
