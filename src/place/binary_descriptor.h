#pragma once
// 256-bit binary descriptors (ORB rows of 32 CV_8U) as four 64-bit words, for fast Hamming
// distances and per-bit majority ("median") centres in vocabulary training.

#include <array>
#include <cstdint>
#include <cstring>
#include <vector>

#include <opencv2/core.hpp>

namespace esdslam {

using Descriptor256 = std::array<std::uint64_t, 4>;
constexpr int kDescriptorBytes = 32;

inline int HammingDistance(const Descriptor256& a, const Descriptor256& b) {
  return __builtin_popcountll(a[0] ^ b[0]) + __builtin_popcountll(a[1] ^ b[1]) +
         __builtin_popcountll(a[2] ^ b[2]) + __builtin_popcountll(a[3] ^ b[3]);
}

inline Descriptor256 DescriptorFromBytes(const unsigned char* bytes) {
  Descriptor256 d;
  std::memcpy(d.data(), bytes, kDescriptorBytes);
  return d;
}

// Rows of an N x 32 CV_8U matrix. Throws esdslam::Error on another type or width.
std::vector<Descriptor256> DescriptorsFromMat(const cv::Mat& descriptors);

// Per-bit majority of the selected descriptors (ties -> 0). `indices` must not be empty.
Descriptor256 MajorityDescriptor(const std::vector<Descriptor256>& descriptors, const std::vector<int>& indices);

}  // namespace esdslam
