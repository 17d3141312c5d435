#pragma once
// Synthetic binary descriptors for loop tests: "landmarks" with random 256-bit descriptors,
// observed with a few flipped bits (the descriptor noise of a real re-observation).

#include <cstdint>
#include <random>
#include <vector>

#include <opencv2/core.hpp>

namespace esdslam::test {

inline cv::Mat RandomDescriptors(int count, std::mt19937* rng) {
  cv::Mat out(count, 32, CV_8U);
  for (int r = 0; r < count; ++r) {
    for (int c = 0; c < 32; ++c) out.at<unsigned char>(r, c) = static_cast<unsigned char>((*rng)() & 0xFF);
  }
  return out;
}

// Copy of row `row` of `landmarks` with `flips` distinct random bits flipped.
inline void NoisyCopy(const cv::Mat& landmarks, int row, int flips, std::mt19937* rng, unsigned char* out) {
  for (int c = 0; c < 32; ++c) out[c] = landmarks.at<unsigned char>(row, c);
  std::vector<int> flipped;
  while (static_cast<int>(flipped.size()) < flips) {
    const int bit = static_cast<int>((*rng)() % 256);
    bool seen = false;
    for (const int b : flipped) seen = seen || b == bit;
    if (seen) continue;
    flipped.push_back(bit);
    out[bit / 8] ^= static_cast<unsigned char>(1u << (bit % 8));
  }
}

// An "image" observing landmarks [first, first + count) (wrapping), each with `flips` noisy bits.
inline cv::Mat ObserveLandmarks(const cv::Mat& landmarks, int first, int count, int flips, std::mt19937* rng) {
  cv::Mat out(count, 32, CV_8U);
  for (int i = 0; i < count; ++i) NoisyCopy(landmarks, (first + i) % landmarks.rows, flips, rng, out.ptr<unsigned char>(i));
  return out;
}

}  // namespace esdslam::test
