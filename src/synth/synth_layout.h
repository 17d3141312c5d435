#pragma once
// Static geometry of the synthetic scenes (world frame: x east, y north, z up, origin at the
// centre of the room floor; all boxes axis-aligned, metres).
//   "room" (arc, loop, orbit): a 6 x 5 x 3 m room with six pieces of furniture along the walls.
//   "ring" (corridor): a 10 x 7 x 3 m floor around a 5.5 x 2.5 m central block that reaches the
//   ceiling, so the free space is a ring corridor 2.25 m wide, with furniture along both sides.
//   Its surfaces are sparser (plain areas between the shapes, fewer posters), as in a building.

#include <vector>

#include "common/geometry.h"
#include "synth/synth_options.h"
#include "synth/texture.h"

namespace esdslam {

struct StaticBox {
  Vec3 centre;
  Vec3 half_size;
};

struct SceneLayout {
  Vec3 room_half_size;               // the room box (seen from inside), centred at (0, 0, half z)
  std::vector<StaticBox> furniture;  // static boxes seen from outside (the ring's block included)
  TextureStyle room_style;           // walls, floor and ceiling
  TextureStyle furniture_style;
};

// The layout of options.trajectory ("corridor" -> ring, otherwise room).
SceneLayout MakeSceneLayout(const SynthOptions& options);

}  // namespace esdslam
