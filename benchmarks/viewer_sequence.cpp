#include "viewer_sequence.h"

#include "synth/sequence_writer.h"
#include "synth/synth_options.h"
#include "synth/synthetic_scene.h"

namespace esdslam {

void WriteViewerBenchSequence(const std::string& dir, int frames) {
  SynthOptions options = SynthPreset("dynamic");
  options.num_frames = frames;
  WriteSynthSequence(SyntheticScene(options), dir);
}

}  // namespace esdslam
