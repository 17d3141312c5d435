#include "place/binary_descriptor.h"

#include "common/error.h"

namespace esdslam {

std::vector<Descriptor256> DescriptorsFromMat(const cv::Mat& descriptors) {
  std::vector<Descriptor256> out;
  if (descriptors.empty()) return out;
  if (descriptors.type() != CV_8UC1 || descriptors.cols != kDescriptorBytes)
    throw Error("binary descriptors must be N x 32 CV_8U rows (256-bit ORB)");
  out.reserve(descriptors.rows);
  for (int r = 0; r < descriptors.rows; ++r) out.push_back(DescriptorFromBytes(descriptors.ptr<unsigned char>(r)));
  return out;
}

Descriptor256 MajorityDescriptor(const std::vector<Descriptor256>& descriptors, const std::vector<int>& indices) {
  std::array<int, 256> ones{};
  for (const int index : indices) {
    const Descriptor256& d = descriptors[index];
    for (int w = 0; w < 4; ++w) {
      std::uint64_t bits = d[w];
      while (bits != 0) {
        const int bit = __builtin_ctzll(bits);
        ++ones[w * 64 + bit];
        bits &= bits - 1;
      }
    }
  }
  const int count = static_cast<int>(indices.size());
  Descriptor256 centre{};
  for (int i = 0; i < 256; ++i) {
    if (2 * ones[i] > count) centre[i / 64] |= std::uint64_t{1} << (i % 64);
  }
  return centre;
}

}  // namespace esdslam
