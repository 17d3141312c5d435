#pragma once
// The static dense map: the keyframes' static points in an AnchoredVoxelMap (memory bounded by
// the occupied volume, points stored in their anchor keyframe's frame) plus, per keyframe, its
// pose at hand-off and its coarse OctoMap rays (KeyframeRays, about 17 kB for a 640x480 keyframe
// at the default OctoMap settings). Everything is built at the keyframe poses the caller passes
// in, so a map built after bundle adjustment or loop closure follows the corrected keyframes;
// keyframes missing from those poses use their hand-off pose.
//
// Threading: every method may be called from any thread. One internal mutex guards the state; no
// other lock is taken while it is held; back-projection, outlier removal and ray casting run
// outside it (rays are immutable once stored and shared by reference counting).

#include <map>
#include <mutex>
#include <vector>

#include "dense/anchored_voxel_map.h"
#include "dense/dense_options.h"
#include "dense/depth_backprojector.h"
#include "dense/point_cloud.h"
#include "io/trajectory_io.h"

namespace esdslam {

// One keyframe handed to the dense map. Images are shared (cv::Mat reference counting), not
// copied: the producer must not write to them afterwards.
struct DenseKeyframe {
  long id = 0;            // keyframe id, unique per map
  double timestamp = 0;   // seconds
  Rigid3 world_from_cam;  // pose at hand-off
  cv::Mat bgr;            // CV_8UC3
  cv::Mat depth_m;        // CV_32F metres, 0 = invalid
  cv::Mat dynamic_mask;   // empty or CV_8U, nonzero = dynamic
};

struct PosedRays {
  long keyframe_id = 0;
  Rigid3 world_from_cam;
  KeyframeRays rays;
};

struct DenseMapStats {
  std::size_t keyframes = 0;
  std::size_t points = 0;          // stored points (about one per occupied voxel)
  std::size_t point_bytes = 0;     // AnchoredVoxelMap::memory_bytes()
  std::size_t ray_bytes = 0;       // every keyframe's KeyframeRays
  long reindexed_anchors = 0;      // keyframes re-indexed after pose changes, summed over the run
  std::size_t reindexed_points = 0;  // points those re-indexings moved
  std::size_t carved_points = 0;     // points removed by free-space evidence (dense/free_space.h)
};

class DenseMap {
 public:
  DenseMap(const PinholeCamera& camera, const DenseOptions& options);

  // Back-projects `keyframe` (no lock held), re-indexes the keyframes whose pose in `poses` moved
  // a point by more than a quarter voxel (`behind`: by a voxel; bundle adjustment nudges most
  // keyframes of a small scene by millimetres every time, and re-indexing all of them costs more
  // than the integration itself), applies its depth's free-space evidence to the stored points
  // (Dense.freeSpaceCarving, dense/free_space.h: every valid reading, masked or not, since a
  // person in front of a point only occludes it), then integrates it at its pose in `poses`
  // (else its hand-off pose).
  void Integrate(const DenseKeyframe& keyframe, const KeyframePoses& poses, bool behind = false);

  // Every keyframe's world_from_cam: from `poses` when present, else the hand-off pose.
  KeyframePoses Resolve(const KeyframePoses& poses) const;
  // World-frame cloud at `poses`: one point per voxel, then optional statistical outlier removal.
  // Also re-indexes the keyframes that moved (the stored map shrinks when corrected poses bring
  // copies of a surface together; the map's content does not change).
  PointCloud BuildGlobalCloud(const KeyframePoses& poses) const;
  // Every keyframe's timestamp and resolved pose, in id order (e.g. for `esdslam map --trajectory`).
  std::vector<StampedPose> StampedPoses(const KeyframePoses& poses) const;
  // Every keyframe's rays at its resolved pose, in id order.
  std::vector<PosedRays> RaysAt(const KeyframePoses& poses) const;
  // Ray end points in the camera frame (metres).
  std::vector<Eigen::Vector3f> RayEndpoints(const KeyframeRays& rays) const { return backprojector_.RayEndpoints(rays); }

  DenseMapStats stats() const;
  const DenseOptions& options() const { return options_; }
  const PinholeCamera& camera() const { return backprojector_.camera(); }

 private:
  struct KeyframeRecord {
    double timestamp = 0;
    Rigid3 handoff_world_from_cam;
    KeyframeRays rays;
  };
  KeyframePoses ResolveLocked(const KeyframePoses& poses) const;

  DenseOptions options_;
  DepthBackprojector backprojector_;  // immutable after construction
  mutable std::mutex mutex_;
  mutable AnchoredVoxelMap points_;  // mutable: its voxel index is re-keyed by const builds
  std::map<long, KeyframeRecord> keyframes_;
  mutable long reindexed_anchors_ = 0;
};

}  // namespace esdslam
