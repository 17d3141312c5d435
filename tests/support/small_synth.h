#pragma once
// A synthetic preset at half resolution (320x240, the same field of view): the same geometry,
// four times fewer rays, for tests that need speed more than pixels.

#include <string>

#include "synth/synth_options.h"

namespace esdslam::testing {

// frames < 0: the preset's own length.
inline SynthOptions SmallSynthOptions(const std::string& preset, int frames = -1) {
  SynthOptions options = SynthPreset(preset);
  if (frames >= 0) options.num_frames = frames;
  options.intrinsics.width = 320;
  options.intrinsics.height = 240;
  options.intrinsics.fx = options.intrinsics.fy = 262.5;
  options.intrinsics.cx = 159.5;
  options.intrinsics.cy = 119.5;
  return options;
}

}  // namespace esdslam::testing
