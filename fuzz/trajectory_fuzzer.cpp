// Fuzz target: the TUM trajectory reader (esdslam eval, ground truth).
#include "common/error.h"
#include "fuzz/fuzz_input.h"
#include "io/trajectory_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = esdslam::fuzz::WriteScratch("trajectory.txt", data, size);
  try {
    esdslam::ReadTumTrajectory(path);
  } catch (const esdslam::Error&) {
  }
  return 0;
}
