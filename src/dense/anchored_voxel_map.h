#pragma once
// The dense map's points, with memory bounded by the occupied volume, not by the number of
// keyframes: at most one point per occupied world voxel (cube of side voxel_size), stored in the
// camera frame of the keyframe that first observed that voxel (its "anchor"). A point's world
// position is always (current pose of its anchor) * (stored position), so the map follows pose
// corrections (bundle adjustment, loop closure) without keeping or re-reading images.
//
// Integrate() adds one keyframe's camera-frame points: a point that falls into a voxel already
// holding a map point is averaged into it (moved into the anchor's frame with the current poses,
// weighted by the number of pixels each side has seen), as is a point in an empty voxel that has
// an existing point on its viewing ray (less than 45 degrees off it) within max(voxel, 2 sigma(z)),
// sigma(z) = depth_noise_at_1m * z^2 the sensor's depth noise: depth noise scatters a surface
// along the ray, and without this the noise tails would fill a band of voxels around every
// surface as observations accumulate. Otherwise it starts a new map point anchored to the keyframe.
// A band still grows from readings beyond the radius, but far more slowly (tests/dense). Readings
// are averaged with weight 1 / max(z, 0.5 m)^4, their inverse depth variance: a surface seen from
// 1 m and from 4 m lies where the near view put it.
//
// CarveFreeSpace() removes points that later views see through (dense/free_space.h); each point
// keeps its evidence count for that.
//
// The voxel index is valid for the anchor poses it was built with. UpdatePoses() re-indexes the
// points of every anchor whose pose moved a point by more than a threshold (default a quarter
// voxel), merging points that now share a voxel (a loop closure that brings a drifted second copy of a wall onto the
// first one halves its storage). Smaller pose changes can leave two points of one surface in
// neighbouring voxels; Extract() re-voxelises at the given poses, so the output has one point per
// voxel in any case.
//
// Not thread-safe: DenseMap serialises access.

#include <cstdint>
#include <map>
#include <unordered_map>
#include <vector>

#include "dense/free_space.h"
#include "dense/point_cloud.h"

namespace esdslam {

using KeyframePoses = std::map<long, Rigid3>;  // keyframe id -> world_from_cam

class AnchoredVoxelMap {
 public:
  // depth_noise_at_1m: sigma of the depth reading at 1 m (metres); 0 = exact depth.
  explicit AnchoredVoxelMap(double voxel_size, double depth_noise_at_1m = 0.0);

  // points_cam: one keyframe's points in its camera frame (metres), e.g. back-projected pixels.
  // world_from_cam: the keyframe's current pose; the other anchors are used at their indexed
  // poses, so call UpdatePoses() first. Integrating a keyframe id twice adds to its points.
  void Integrate(long keyframe_id, const Rigid3& world_from_cam, const PointCloud& points_cam);

  // Re-indexes the anchors whose pose in `poses` moves a point by more than threshold_voxels
  // voxels (anchors missing from `poses` keep their indexed pose). Returns how many it re-indexed.
  int UpdatePoses(const KeyframePoses& poses, double threshold_voxels = 0.25);

  // Free-space consistency (dense/free_space.h): classifies every stored point (at its anchor's
  // indexed pose) in `view`, updates its evidence and removes the points whose evidence runs out.
  // Returns the number removed. Call it before integrating the view's own points.
  std::size_t CarveFreeSpace(const FreeSpaceView& view, int max_evidence);

  // World-frame cloud, one point per voxel, at `poses` (anchors missing there: indexed pose).
  PointCloud Extract(const KeyframePoses& poses) const;

  double voxel_size() const { return voxel_size_; }
  std::size_t num_points() const { return live_points_; }
  std::size_t num_anchors() const { return anchors_.size(); }
  std::size_t num_reindexed_points() const { return reindexed_points_; }  // summed over all UpdatePoses calls
  std::size_t num_carved_points() const { return carved_points_; }        // summed over all CarveFreeSpace calls
  // Bytes held by the points and the voxel index (containers' capacity plus an estimate of the
  // hash table's node and bucket overhead).
  std::size_t memory_bytes() const;
  // Self-check for tests: live points whose voxel index entry is missing or names another point,
  // plus index entries that name a hole.
  std::size_t CountIndexErrors() const;

 private:
  struct StoredPoint {
    Eigen::Vector3f position;  // anchor camera frame, metres: weighted mean of the observations
    float weight = 0;          // pixels averaged; 0 = merged into another point (a hole)
    std::uint64_t key = 0;     // voxel of the point at its anchor's indexed pose
    std::uint16_t color_x128[3] = {0, 0, 0};  // mean RGB * 128
    std::uint8_t evidence = 1;  // free-space evidence: keyframes that saw it, less those that saw through it
  };
  struct Anchor {
    long keyframe_id = 0;
    Rigid3 world_from_cam;            // indexed pose
    Eigen::Matrix3f rotation;         // of world_from_cam, float copies for the inner loops
    Eigen::Vector3f translation;
    float max_range = 0;              // largest |position| of its points (m), bounds a pose change's effect
    std::vector<StoredPoint> points;
    std::size_t holes = 0;
  };
  struct PointRef {
    std::uint32_t anchor = 0;
    std::uint32_t index = 0;
  };

  std::uint32_t AnchorSlot(long keyframe_id, const Rigid3& world_from_cam);
  void SetAnchorPose(Anchor* anchor, const Rigid3& world_from_cam);
  // Adds an observation at world position p_world to the point `ref` (into its anchor's frame).
  void Accumulate(const PointRef& ref, const Eigen::Vector3f& p_world, const float color_x128[3], float weight);
  // The nearest point found in the voxels stepped through along the unit viewing ray `ray` (both
  // ways, up to `radius` but at most 64 voxels) that lies within `radius` of p_world and less than 45 degrees off the
  // ray, else null.
  const PointRef* NearPointOnRay(const Eigen::Vector3f& p_world, const Eigen::Vector3f& ray, float radius) const;
  // Indexes point `index` of `slot` at its anchor's pose; merges it into an existing point instead.
  void Reinsert(std::uint32_t slot, std::uint32_t index);
  void Compact(std::uint32_t slot);
  Eigen::Vector3f WorldPosition(const Anchor& anchor, const StoredPoint& point) const {
    return anchor.rotation * point.position + anchor.translation;
  }

  double voxel_size_;
  double depth_noise_at_1m_;
  std::vector<Anchor> anchors_;
  std::unordered_map<long, std::uint32_t> slot_of_keyframe_;
  std::unordered_map<std::uint64_t, PointRef> index_;
  std::size_t live_points_ = 0;
  std::size_t reindexed_points_ = 0;
  std::size_t carved_points_ = 0;
};

}  // namespace esdslam
