#pragma once
// Global relocalization of a LOST frame (ORB-SLAM2's Tracking::Relocalization, RGB-D): BoW
// candidates from the keyframe database; per candidate, BoW matching of the frame's keypoints to
// the candidate's map points, PnP RANSAC, motion-only BA on the inliers, then projection search
// of the candidate's remaining points (coarse then fine window) and BA again. The first candidate
// reaching min_final_inliers wins; the frame then holds its pose and inlier associations and the
// tracker continues with local-map tracking in the same map.
//
// Runs on the tracking thread under Map::update_mutex.

#include <vector>

#include "place/bow_matcher.h"
#include "place/place_recognition.h"
#include "robust/pnp_ransac.h"
#include "optim/pose_optimizer.h"
#include "tracking/frame.h"

namespace esdslam {

struct RelocalizerOptions {
  BowMatchOptions bow;          // ORB-SLAM2 relocalization: ratio 0.75, orientation check
  int min_bow_matches = 15;     // candidates with fewer BoW matches are skipped
  int max_candidates = 20;      // best-scored BoW candidates tried per frame
  PnpRansacOptions pnp;         // min_inliers 10 (ORB-SLAM2 PnPsolver)
  int min_optimized_inliers = 10;
  int min_final_inliers = 50;
  double coarse_radius_factor = 2.5;  // projection window = (2.5|4) x factor x level scale px
  double fine_radius_factor = 0.75;
  RelocalizerOptions() { pnp.min_inliers = 10; }
  void Check() const;
};

struct RelocalizationStats {
  int candidates = 0;   // BoW candidates returned by the database
  int tried = 0;        // candidates that reached PnP
  int inliers = 0;      // final inliers (0 on failure)
};

class Relocalizer {
 public:
  // `places` must outlive the relocalizer.
  Relocalizer(PlaceRecognition* places, const RelocalizerOptions& options = {});

  // On success returns the candidate keyframe used (the frame's reference), with frame->
  // cam_from_world and frame->map_points (inliers only, outlier flags cleared) set; otherwise
  // nullptr and the frame's associations cleared. `map_keyframes` are indexed first when missing.
  KeyFrame* Relocalize(Frame* frame, const PoseOptimizerOptions& pose_options,
                       const std::vector<KeyFrame*>& map_keyframes, RelocalizationStats* stats = nullptr);

  PlaceRecognition* places() const { return places_; }

 private:
  // BoW matches of the frame to the candidate's map points (frame->map_points overwritten).
  int MatchCandidate(Frame* frame, const ImageBow& frame_bow, KeyFrame* candidate) const;
  // PnP + BA + projection search from a matched candidate; true when it reaches min_final_inliers.
  bool SolveCandidate(Frame* frame, KeyFrame* candidate, const PoseOptimizerOptions& pose_options, int* inliers) const;

  PlaceRecognition* places_;
  RelocalizerOptions options_;
};

}  // namespace esdslam
