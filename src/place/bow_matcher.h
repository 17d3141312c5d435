#pragma once
// Descriptor matching between two images through their BoW direct indices (ORB-SLAM2's
// SearchByBoW): only descriptors under the same vocabulary node are compared. Works on indices,
// so it serves keyframe-keyframe (loop closing) and keyframe-frame (relocalization) matching.

#include <vector>

#include "place/bow_vector.h"
#include "map/feature_set.h"

namespace esdslam {

struct BowMatchOptions {
  int max_distance = 50;         // Hamming bits (ORB-SLAM2 TH_LOW)
  double ratio = 0.75;           // best < ratio * second best
  bool check_orientation = true; // keep the 3 dominant keypoint-rotation bins (30 degrees wide)
  void Check() const;
};

// For each `train` keypoint with train_usable[i], finds the best `query` keypoint (with
// query_usable[j]) under the same direct-index node. Returns query_to_train (size query.size(),
// -1 = unmatched); a query keypoint is matched at most once (first train keypoint in node order
// wins). Empty usable vectors mean "all usable".
std::vector<int> MatchByDirectIndex(const FeatureSet& train, const FeatureVector& train_index,
                                    const std::vector<bool>& train_usable, const FeatureSet& query,
                                    const FeatureVector& query_index, const std::vector<bool>& query_usable,
                                    const BowMatchOptions& options);

// Match ids (any ints) whose rotation (keypoint angle difference, degrees) is outside the three
// most populated 30-degree bins (2nd/3rd only with >= 10% of the largest).
std::vector<int> OrientationOutliers(const std::vector<std::pair<float, int>>& rotation_and_id);

}  // namespace esdslam
