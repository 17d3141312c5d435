#pragma once
// Synthetic test sequences written once per test process (definition in
// dynamic_sequence.cpp: synth/sequence_writer.h and semantic/segmenter.h both
// define kVocPersonClass, so they cannot share a translation unit).
#include <string>

namespace esdslam::testing {

// The "dynamic" preset with `frames` frames (no supersampling) in a temp folder, plus run.yaml:
// the scene's settings with the folder segmenter on its labels/ (perfect VOC labels) and no
// safety dilation of the refined mask (Dynamic.maskDilation: 0), so precision measures the mask.
const std::string& DynamicTestSequence(int frames);

// The "occlusion" preset (no supersampling) in a temp folder, plus run.yaml: the scene's settings
// with the folder segmenter on its labels/ (the default mask dilation kept).
const std::string& OcclusionTestSequence();

// The "rolling" preset as it is (rolling shutter with a 0.025 s readout, its settings.yaml
// holding Camera.readoutTime) in a temp folder.
const std::string& RollingTestSequence();

}  // namespace esdslam::testing
