#include "synth/synth_layout.h"

namespace esdslam {
namespace {

// Clear of the arc, loop and orbit camera paths and of the mover lanes (synth_paths.cpp).
SceneLayout RoomLayout() {
  SceneLayout layout;
  layout.room_half_size = Vec3(3.0, 2.5, 1.5);
  layout.furniture = {
      {{2.65, -0.6, 0.45}, {0.3, 0.6, 0.45}},   // cabinet, east wall
      {{-2.72, 0.5, 1.0}, {0.25, 0.5, 1.0}},    // tall shelf, west wall
      {{-0.6, 2.3, 0.4}, {0.7, 0.2, 0.4}},      // sideboard, north wall
      {{1.6, 2.3, 0.25}, {0.35, 0.2, 0.25}},    // crate, north wall
      {{-2.4, -2.1, 0.3}, {0.4, 0.3, 0.3}},     // low box, south-west corner
      {{0.9, 2.46, 1.65}, {0.45, 0.04, 0.3}},   // picture frame on the north wall
  };
  layout.furniture_style.base_bgr = cv::Vec3b(90, 110, 140);
  return layout;
}

// The corridor path runs along the middle of the ring (1.125 m from both sides); every piece
// leaves >= 0.6 m to it.
SceneLayout RingLayout() {
  SceneLayout layout;
  layout.room_half_size = Vec3(5.0, 3.5, 1.5);
  layout.furniture = {
      {{0.0, 0.0, 1.5}, {2.75, 1.25, 1.5}},     // central block, floor to ceiling
      {{4.75, -1.5, 0.45}, {0.25, 0.5, 0.45}},  // cabinet, east wall
      {{4.8, 1.6, 1.0}, {0.2, 0.45, 1.0}},      // shelf, east wall
      {{-1.5, 3.25, 0.4}, {0.7, 0.25, 0.4}},    // sideboard, north wall
      {{2.2, 3.3, 0.25}, {0.35, 0.2, 0.25}},    // crate, north wall
      {{-4.75, 0.3, 0.9}, {0.25, 0.6, 0.9}},    // tall cabinet, west wall
      {{1.0, -3.2, 0.3}, {0.5, 0.3, 0.3}},      // low box, south wall
      {{-2.5, -3.25, 0.25}, {0.8, 0.25, 0.25}}, // bench, south wall
      {{0.0, -1.45, 0.35}, {0.4, 0.2, 0.35}},   // planter against the block's south face
      {{-1.2, 1.29, 1.6}, {0.5, 0.04, 0.35}},   // picture on the block's north face
  };
  // About half of each surface keeps its plain base colour.
  layout.room_style.coverage = {0.3, 0.2, 0.15, 0.08, 0.05, 0.03};
  layout.room_style.posters_per_m2 = 0.05;
  layout.furniture_style = layout.room_style;
  layout.furniture_style.base_bgr = cv::Vec3b(90, 110, 140);
  return layout;
}

}  // namespace

SceneLayout MakeSceneLayout(const SynthOptions& options) {
  return options.trajectory == "corridor" ? RingLayout() : RoomLayout();
}

}  // namespace esdslam
