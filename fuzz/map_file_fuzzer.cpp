// Fuzz target: the binary map file (esdslam run --load-map). The camera is the seed's
// (map/map_serialization.h checks it against the file), see fuzz/seeds.cpp.
#include <cstdlib>

#include "common/error.h"
#include "fuzz/fuzz_input.h"
#include "fuzz/seeds.h"
#include "map/map.h"
#include "map/map_serialization.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  if (const char* seed = std::getenv("ESDSLAM_FUZZ_WRITE_SEED")) {
    esdslam::fuzz::WriteMapSeed(seed);
    std::exit(0);
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::shared_ptr<const esdslam::RgbdRig> rig = esdslam::fuzz::SeedRig();
  const std::string path = esdslam::fuzz::WriteScratch("map.bin", data, size);
  esdslam::Map map;
  try {
    esdslam::LoadMap(path, rig, &map);
  } catch (const esdslam::Error&) {
  }
  return 0;
}
