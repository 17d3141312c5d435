#pragma once
// The refinement step shared by the RANSAC estimators: re-fit the model on its inliers and
// re-select the inliers, while the inlier count does not drop, until the inlier set is stable.

#include <vector>

namespace esdslam {

// `refit(inliers, &model)` fits the model on the flagged matches (starting from the model it is
// given) and returns false when the fit fails; `select(model, &inliers)` flags every match within
// the error bound and returns their count. Runs at most `max_rounds` rounds, and none once fewer
// than `min_sample` inliers remain. On return model, inliers and num_inliers belong together.
template <class Model, class Refit, class Select>
void RefineOnInliers(int max_rounds, int min_sample, const Refit& refit, const Select& select, Model* model,
                     std::vector<bool>* inliers, int* num_inliers) {
  std::vector<bool> reselected;
  for (int round = 0; round < max_rounds && *num_inliers >= min_sample; ++round) {
    Model refined = *model;
    if (!refit(*inliers, &refined)) break;
    const int count = select(refined, &reselected);
    if (count < *num_inliers) break;
    const bool stable = reselected == *inliers;
    *model = refined;
    *inliers = reselected;
    *num_inliers = count;
    if (stable) break;
  }
}

}  // namespace esdslam
