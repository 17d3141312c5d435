#include "tracking/frame_pose.h"

#include <vector>

#include "map/map_point.h"

namespace esdslam {

int OptimizeFramePose(Frame* frame, const PoseOptimizerOptions& options, const PosePrior* prior) {
  const FeatureSet& features = frame->features();
  std::vector<PoseObservation> observations;
  std::vector<int> indices;  // keypoint of each observation
  for (int i = 0; i < frame->size(); ++i) {
    MapPoint* point = frame->map_points[i];
    if (point == nullptr) continue;
    PoseObservation observation;
    observation.point_world = point->position();
    observation.pixel = features.pixel(i);
    observation.right_u = features.right_u[i];
    observation.information = features.rig->pyramid.inv_level_sigma2[features.level(i)];
    observation.outlier = frame->outlier[i];
    observations.push_back(observation);
    indices.push_back(i);
  }
  if (observations.empty()) return 0;
  const int inliers = OptimizePose(features.rig->camera, features.rig->bf, options, &observations, &frame->cam_from_world, prior);
  for (std::size_t k = 0; k < indices.size(); ++k) frame->outlier[indices[k]] = observations[k].outlier;
  return inliers;
}

}  // namespace esdslam
