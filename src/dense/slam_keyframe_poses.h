#pragma once
// KeyframePoseSource reading the SLAM map: the current world_from_cam of every keyframe handed to
// the dense map, after bundle adjustment and loop closure. A culled keyframe keeps its points: its
// pose follows its live spanning-tree ancestor through the stored cam_from_parent (LiveAncestor),
// as the trajectory output does.
//
// Threads: Register() from the producer (tracking) thread, Poses() from any thread. Poses() copies
// the registry under its own mutex, releases it, then takes Map::update_mutex to read consistent
// poses; the map pointers stay valid because the Map frees nothing before it is destroyed.

#include <mutex>
#include <vector>

#include "dense/anchored_voxel_map.h"
#include "map/map.h"

namespace esdslam {

class SlamKeyframePoses {
 public:
  explicit SlamKeyframePoses(Map* map) : map_(map) {}

  void Register(KeyFrame* keyframe);
  KeyframePoses Poses() const;  // by KeyFrame::id()

 private:
  Map* map_;
  mutable std::mutex mutex_;
  std::vector<KeyFrame*> keyframes_;
};

}  // namespace esdslam
