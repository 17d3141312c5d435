// Fuzz target: the sequence lists. The first byte picks the file the rest becomes: rgb.txt
// (depth.txt valid), depth.txt (rgb.txt valid) or an ORB-SLAM2 association file.
#include <fstream>

#include "common/error.h"
#include "fuzz/fuzz_input.h"
#include "io/tum_sequence.h"

namespace {

void WriteText(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::string dir = esdslam::fuzz::ScratchDir();
  const std::string valid_rgb = "# rgb\n1.0 rgb/1.0.png\n2.0 rgb/2.0.png\n";
  const std::string valid_depth = "# depth\n1.01 depth/1.01.png\n2.01 depth/2.01.png\n";
  esdslam::AssociationOptions options;
  switch (data[0] % 3) {
    case 0:
      esdslam::fuzz::WriteScratch("rgb.txt", data + 1, size - 1);
      WriteText(dir + "/depth.txt", valid_depth);
      break;
    case 1:
      WriteText(dir + "/rgb.txt", valid_rgb);
      esdslam::fuzz::WriteScratch("depth.txt", data + 1, size - 1);
      break;
    default:
      options.association_file = esdslam::fuzz::WriteScratch("associations.txt", data + 1, size - 1);
      break;
  }
  try {
    esdslam::TumSequence::Open(dir, options);
  } catch (const esdslam::Error&) {
  }
  return 0;
}
