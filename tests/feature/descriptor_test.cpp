#include "feature/descriptor.h"

#include <random>

#include <gtest/gtest.h>

#include "common/error.h"

namespace esdslam {
namespace {

cv::Mat RandomDescriptor(std::mt19937* rng) {
  cv::Mat d(1, 32, CV_8U);
  std::uniform_int_distribution<int> byte(0, 255);
  for (int i = 0; i < 32; ++i) d.at<unsigned char>(0, i) = static_cast<unsigned char>(byte(*rng));
  return d;
}

TEST(DescriptorDistance, CountsFlippedBits) {
  std::mt19937 rng(7);
  const cv::Mat a = RandomDescriptor(&rng);
  EXPECT_EQ(DescriptorDistance(a, a), 0);
  cv::Mat b = a.clone();
  // Flip 37 distinct bits spread over all bytes.
  for (int k = 0; k < 37; ++k) {
    const int bit = (k * 7) % 256;
    b.at<unsigned char>(0, bit / 8) ^= static_cast<unsigned char>(1u << (bit % 8));
  }
  EXPECT_EQ(DescriptorDistance(a, b), 37);
  EXPECT_EQ(DescriptorDistance(b, a), 37);
  cv::Mat inverted;
  cv::bitwise_not(a, inverted);
  EXPECT_EQ(DescriptorDistance(a, inverted), 256);
}

TEST(DescriptorDistance, MatchesBitByBitCountOnRandomPairs) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 100; ++trial) {
    const cv::Mat a = RandomDescriptor(&rng), b = RandomDescriptor(&rng);
    int expected = 0;
    for (int i = 0; i < 32; ++i)
      for (int bit = 0; bit < 8; ++bit)
        expected += ((a.at<unsigned char>(0, i) >> bit) & 1) != ((b.at<unsigned char>(0, i) >> bit) & 1);
    EXPECT_EQ(DescriptorDistance(a, b), expected);
  }
}

TEST(DescriptorDistance, WorksOnRowsOfADescriptorMatrix) {
  std::mt19937 rng(3);
  cv::Mat all(4, 32, CV_8U);
  for (int r = 0; r < 4; ++r) RandomDescriptor(&rng).copyTo(all.row(r));
  EXPECT_EQ(DescriptorDistance(all.row(1), all.row(2)), DescriptorDistance(all.ptr(1), all.ptr(2)));
}

TEST(DescriptorDistance, RejectsWrongShapes) {
  EXPECT_THROW(DescriptorDistance(cv::Mat(1, 16, CV_8U), cv::Mat(1, 16, CV_8U)), Error);
  EXPECT_THROW(DescriptorDistance(cv::Mat(1, 32, CV_32F), cv::Mat(1, 32, CV_32F)), Error);
}

}  // namespace
}  // namespace esdslam
