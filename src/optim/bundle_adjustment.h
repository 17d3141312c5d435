#pragma once
// Local bundle adjustment over a covisible window (ORB-SLAM2's Optimizer::LocalBundleAdjustment)
// on plain map-agnostic data: our fixed-block Schur solver for local windows, Ceres for large ones.

#include <atomic>
#include <vector>

#include "camera/pinhole_camera.h"
#include "common/geometry.h"

namespace esdslam {

struct BaKeyframe {
  Rigid3 cam_from_world;
  bool fixed = false;  // held constant (bitwise unchanged)
};
struct BaPoint {
  Vec3 position_world;
  bool fixed = false;
};
struct BaObservation {
  int keyframe = 0;        // index into BaProblem::keyframes
  int point = 0;           // index into BaProblem::points
  Vec2 pixel;              // undistorted keypoint (u, v), px
  double right_u = -1;     // virtual right-camera u; < 0: 2-D residual
  double information = 1;  // inverse sigma^2 of the keypoint's pyramid level
  bool outlier = false;    // out: set by the optimiser
};
struct BaProblem {
  std::vector<BaKeyframe> keyframes;
  std::vector<BaPoint> points;
  std::vector<BaObservation> observations;
};

struct BundleAdjustmentOptions {
  int iterations_first = 5;    // with Huber loss, over all observations
  int iterations_second = 10;  // without robust loss, over the inliers
  double chi2_mono = 5.991;
  double chi2_stereo = 7.815;
  int num_threads = 1;  // Ceres' threads (large windows only)
  // Windows with at most this many free keyframes are solved by optim/schur_lm.h (dense reduced
  // camera system, fixed-size blocks); larger ones by Ceres' sparse Schur solver.
  int max_dense_keyframes = 60;
  void Check() const;
};

struct BaSummary {
  double initial_cost = 0;  // Ceres cost (0.5 * sum of squared weighted residuals) before
  double final_cost = 0;    // ... and after (of the last solve)
  int outliers = 0;         // observations flagged outlier at the end
  bool aborted = false;     // stopped early by the stop flag
};

// Optimises with Huber, marks outliers (chi2 above threshold or point behind the camera),
// optimises again without them and without robust loss, then re-flags outliers with the final
// estimates. Updates poses and points in place. `stop` (may be null) aborts early when set by
// another thread (e.g. a new keyframe arrived); the estimates are then still consistent (the
// best iterate so far). Throws Error on out-of-range indices.
BaSummary BundleAdjust(const PinholeCamera& camera, double bf, const BundleAdjustmentOptions& options,
                       BaProblem* problem, const std::atomic<bool>* stop = nullptr);

}  // namespace esdslam
