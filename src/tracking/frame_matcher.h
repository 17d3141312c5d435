#pragma once
// Descriptor matching between a Frame and map points (ORB-SLAM2's ORBmatcher searches used by
// tracking). Searches return their associations as values; dynamic keypoints are never matched.

#include <vector>

#include "tracking/frame.h"

namespace esdslam {

// Keeps only matches whose rotation change (keypoint angle difference) falls in the three most
// populated 30-degree histogram bins (the 2nd/3rd only with >= 10% of the largest). `angle_pairs`
// holds (query angle - train angle, match id); returns the ids to discard.
std::vector<int> RotationInconsistentMatches(const std::vector<std::pair<float, int>>& angle_pairs);

// What a search found, as a value; the frame is not touched (ApplyMatches writes it).
struct FrameMatches {
  std::vector<MapPoint*> map_points;  // per keypoint of the frame: its association after the search
  std::vector<int> matched;           // keypoints the search associated, in order (before the rotation check)
  int count = 0;                      // associations the search made and kept
};

// frame->map_points = matches.map_points; the keypoints matched lose their outlier flag.
void ApplyMatches(const FrameMatches& matches, Frame* frame);

// Projects the last frame's (non-outlier) map points with current.cam_from_world and matches them
// within `radius_px` * scale of the last keypoint's level (RGB-D: also checks the virtual right
// coordinate). Starts from no association.
FrameMatches SearchByProjection(const Frame& current, const Frame& last, double radius_px);

// Matches projected local map points (Frame::ProjectInFrustum) to the frame's keypoints not yet
// associated with a real map point; starts from the frame's associations. Window:
// radius_factor * (2.5 or 4 by viewing angle) * scale of the predicted level.
FrameMatches SearchLocalPoints(const Frame& frame, const std::vector<PointProjection>& projections,
                               double radius_factor);

// Brute-force matching of the keyframe's map points to the frame's keypoints (mutual best,
// distance <= TH_LOW-ish threshold, ratio test 0.7, rotation consistency). Starts from no association.
FrameMatches SearchKeyFrameBruteForce(const KeyFrame& keyframe, const Frame& frame);

}  // namespace esdslam
