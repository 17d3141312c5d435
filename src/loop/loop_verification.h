#pragma once
// Geometric verification of a loop candidate (ORB-SLAM2's LoopClosing::ComputeSim3 for RGB-D,
// where the scale is known and fixed):
//   1. BoW matching of the current keyframe's map points to the candidate's (direct index);
//   2. rigid RANSAC on those 3-D/3-D matches (both points in their cameras' frames), inliers by
//      reprojection into both views;
//   3. guided mutual matching with the estimate (more 3-D/3-D matches);
//   4. refinement by two-view reprojection (relative_pose_refinement.h), enough inliers;
//   5. projection of the candidate's and its covisible keyframes' points ("loop points") into
//      the current keyframe with the corrected pose: enough matches in total.
// Reads map objects through their own locks (local mapping may run meanwhile).

#include <cstdint>
#include <vector>

#include "place/bow_matcher.h"
#include "place/place_recognition.h"
#include "loop/relative_pose_refinement.h"
#include "robust/rigid_ransac.h"

namespace esdslam {

struct LoopVerificationOptions {
  BowMatchOptions bow;            // ratio 0.75, orientation check (ORB-SLAM2 ComputeSim3)
  int min_bow_matches = 20;
  RigidRansacOptions ransac;      // reprojection inliers, >= 20, scale fixed
  double guided_radius_px = 7.5;  // guided matching window x level scale (SearchBySim3)
  RelativePoseRefinementOptions refinement;
  int min_refined_inliers = 20;
  double projection_radius_factor = 10;  // loop points into the current keyframe
  int min_total_matches = 40;
  void Check() const;
};

struct LoopMatch {
  KeyFrame* current = nullptr;
  KeyFrame* loop = nullptr;                 // the verified candidate
  Rigid3 current_from_loop;                 // cam_current_from_cam_loop, refined
  Rigid3 corrected_cam_from_world;          // current keyframe's pose agreeing with the loop keyframe
  std::vector<MapPoint*> matched_points;    // per current keypoint: the loop-side point (or null)
  std::vector<MapPoint*> loop_points;       // points of the loop keyframe and its covisible ones
  int bow_matches = 0, ransac_inliers = 0, refined_inliers = 0, total_matches = 0;
};

// Verifies `candidate` as a loop for `current` (both indexed in `places`). Fills *match (also
// with the partial counts on failure, for logging) and returns true on success.
bool VerifyLoopCandidate(KeyFrame* current, KeyFrame* candidate, const PlaceRecognition& places,
                         const LoopVerificationOptions& options, std::uint32_t seed, LoopMatch* match);

}  // namespace esdslam
