#pragma once
// The viewer benchmark's input: a synthetic sequence on disk (synth/sequence_writer.h). In its
// own translation unit: synth/sequence_writer.h and semantic/segmenter.h (which the pipeline
// brings) both define kVocPersonClass (as tests/system/dynamic_sequence.h explains).
#include <string>

namespace esdslam {

// Writes the "dynamic" preset with `frames` frames (settings.yaml included) into dir.
void WriteViewerBenchSequence(const std::string& dir, int frames);

}  // namespace esdslam
