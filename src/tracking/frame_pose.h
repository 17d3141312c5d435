#pragma once
// Motion-only bundle adjustment of one frame on its current map point associations: the single
// pose-optimiser entry point of tracking (the tracker's steps and the relocalizer both call it).

#include "optim/pose_optimizer.h"
#include "tracking/frame.h"

namespace esdslam {

// Refines frame->cam_from_world from the associated points (world frame) and their keypoints,
// weighted by the inverse level variance; frame->outlier is rewritten for every associated
// keypoint (associations themselves are kept). Returns the inlier count (0, pose untouched, when
// the frame has no association). `prior` (null = none): a Gaussian prior on the pose (OptimizePose).
int OptimizeFramePose(Frame* frame, const PoseOptimizerOptions& options, const PosePrior* prior = nullptr);

}  // namespace esdslam
