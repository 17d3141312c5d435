#pragma once
// Valid binary seed files for the map and vocabulary fuzz targets, made by the library's own
// writers (there is no small real file to ship): run a target with ESDSLAM_FUZZ_WRITE_SEED=PATH
// and it writes its seed to PATH and exits (tools/fuzz.sh does this before fuzzing).
#include <memory>
#include <string>

#include "map/rgbd_rig.h"

namespace esdslam::fuzz {

// The rig the map seed is written for (and the map target loads with).
std::shared_ptr<const RgbdRig> SeedRig();
// Three keyframes, the points they share (map/map_serialization.h format).
void WriteMapSeed(const std::string& path);
// A vocabulary with branching 3, depth 2, trained on random descriptors.
void WriteVocabularySeed(const std::string& path);

}  // namespace esdslam::fuzz
