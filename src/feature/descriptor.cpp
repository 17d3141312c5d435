#include "feature/descriptor.h"

#include <cstdint>
#include <cstring>

#include "common/error.h"

namespace esdslam {

int DescriptorDistance(const unsigned char* a, const unsigned char* b) {
  int distance = 0;
  for (int i = 0; i < 32; i += 8) {
    std::uint64_t wa, wb;
    std::memcpy(&wa, a + i, 8);
    std::memcpy(&wb, b + i, 8);
    distance += __builtin_popcountll(wa ^ wb);
  }
  return distance;
}

int DescriptorDistance(const cv::Mat& a, const cv::Mat& b) {
  if (a.type() != CV_8U || b.type() != CV_8U || a.total() != 32 || b.total() != 32 || !a.isContinuous() ||
      !b.isContinuous())
    throw Error("DescriptorDistance expects two continuous 1x32 CV_8U descriptors");
  return DescriptorDistance(a.ptr<unsigned char>(), b.ptr<unsigned char>());
}

}  // namespace esdslam
