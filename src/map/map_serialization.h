#pragma once
// Binary map files (esdslam run --save-map / --load-map). Little-endian, version-tagged:
//   header: magic "ESDMAP\0\1", u32 version (1), camera fx fy cx cy (f64), width height (i32),
//           u64 keyframe count, u64 map point count
//   keyframe: i64 id, i64 frame id, f64 timestamp, pose cam_from_world (quaternion w x y z,
//           translation x y z; f64), u32 keypoint count N, then per keypoint: raw x y, size,
//           angle, response (f32), octave (i32), undistorted x y, depth, right_u (f32),
//           is_dynamic (u8), 32 descriptor bytes
//   map point: f64 x y z (world), u32 observation count, per observation: i64 keyframe id (as
//           written above), i32 keypoint index
// Only live keyframes and points are written. On load, objects get fresh ids in file order,
// descriptors/normals/distances of points and the covisibility graph and spanning tree are
// recomputed (UpdateConnections in keyframe order), so the loaded map is equivalent, not
// byte-identical in its derived state.

#include <memory>
#include <string>

#include "map/map.h"
#include "map/rgbd_rig.h"

namespace esdslam {

struct MapFileSummary {
  int keyframes = 0;
  int map_points = 0;
  int observations = 0;
};

// Writes the map's live keyframes and points. Caller holds Map::update_mutex (or no other thread
// runs). Throws Error when the file cannot be written.
MapFileSummary SaveMap(const Map& map, const std::string& path);

// Reads a file into an empty map; every keyframe shares `rig`, whose camera must equal the
// file's (fx fy cx cy width height). Throws InputError on a missing, truncated, corrupt or
// incompatible file, Error when `map` is not empty.
MapFileSummary LoadMap(const std::string& path, std::shared_ptr<const RgbdRig> rig, Map* map);

}  // namespace esdslam
