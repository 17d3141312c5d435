#pragma once
// The static dense map: one voxel-downsampled cloud per keyframe, kept in that keyframe's
// camera frame, so that the global map always follows the latest keyframe poses (bundle
// adjustment, loop closure). The global cloud is assembled on demand.
//
// Threading: all methods may be called from any thread; one internal mutex guards the
// keyframe clouds (no other lock is taken while holding it).

#include <map>
#include <mutex>

#include "dense/dense_options.h"
#include "dense/point_cloud.h"

namespace esdslam {

class DenseMap {
 public:
  explicit DenseMap(const DenseOptions& options);

  void SetKeyframeCloud(long keyframe_id, PointCloud cloud_in_cam);
  void RemoveKeyframe(long keyframe_id);
  std::size_t num_keyframes() const;
  std::size_t num_stored_points() const;

  // Global cloud in the world frame from the given keyframe poses (keyframes without a pose
  // are skipped): transform, voxel-downsample, then optional statistical outlier removal.
  PointCloud BuildGlobalCloud(const std::map<long, Rigid3>& world_from_keyframe) const;

  // Keyframe clouds in the world frame with each keyframe's camera centre, for ray casting.
  struct PosedCloud {
    Vec3 sensor_origin_world;
    PointCloud cloud_world;
  };
  std::vector<PosedCloud> PosedClouds(const std::map<long, Rigid3>& world_from_keyframe) const;

  const DenseOptions& options() const { return options_; }

 private:
  DenseOptions options_;
  mutable std::mutex mutex_;
  std::map<long, PointCloud> clouds_in_cam_;
};

}  // namespace esdslam
