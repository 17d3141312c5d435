// The grouped convolution's inner loops: each build against a plain double-precision reference
// on noise, for counts that leave tails of every length, steps as the layer uses them (dilations
// 1-4, a padded row width), and stride-2 rows read up to the last valid input index (the
// buffers are exactly as long as the reads the caller vouches for, so AddressSanitizer sees any
// read past them). The AVX2 build runs only where the CPU has it.
#include "semantic/conv_kernels.h"

#include <cstddef>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

namespace esdslam {
namespace {

std::vector<float> Noise(std::size_t count, int seed) {
  std::vector<float> values(count);
  cv::RNG rng(static_cast<std::uint64_t>(seed));
  for (float& v : values) v = static_cast<float>(rng.uniform(-1.0, 1.0));
  return values;
}

std::vector<const ConvKernels*> Builds() {
  std::vector<const ConvKernels*> builds{&PortableConvKernels()};
  if (const ConvKernels* avx2 = Avx2ConvKernels()) builds.push_back(avx2);
  return builds;
}

TEST(ConvKernels, BestIsTheAvx2BuildExactlyWhenTheCpuHasIt) {
  EXPECT_STREQ(BestConvKernels().name, Avx2ConvKernels() ? "avx2+fma" : "portable");
}

TEST(ConvKernels, MultiplyAddMatchesTheReferenceForEveryTailLength) {
  for (const ConvKernels* kernels : Builds()) {
    for (std::size_t count = 0; count <= 37; ++count) {
      const std::vector<float> src = Noise(count, 1);
      std::vector<float> sums = Noise(count, 2);
      const std::vector<float> before = sums;
      kernels->multiply_add(src.data(), 0.37f, sums.data(), count);
      for (std::size_t k = 0; k < count; ++k)
        EXPECT_NEAR(sums[k], before[k] + 0.37 * src[k], 1e-6) << kernels->name << " count " << count << " k " << k;
    }
  }
}

TEST(ConvKernels, ThreeByThreeMatchesTheReferenceAtEveryDilation) {
  const std::vector<float> taps = Noise(9, 3);
  for (const ConvKernels* kernels : Builds()) {
    for (int dilation = 1; dilation <= 4; ++dilation) {
      for (std::size_t count : {std::size_t{1}, std::size_t{7}, std::size_t{8}, std::size_t{29}, std::size_t{200}}) {
        const std::ptrdiff_t row_step = 23 * dilation, col_step = dilation;
        const std::vector<float> src = Noise(count + static_cast<std::size_t>(2 * row_step + 2 * col_step), 4);
        std::vector<float> sums = Noise(count, 5);
        const std::vector<float> before = sums;
        kernels->multiply_add_3x3(src.data(), row_step, col_step, taps.data(), sums.data(), count);
        for (std::size_t k = 0; k < count; ++k) {
          double expected = before[k];
          for (int ky = 0; ky < 3; ++ky)
            for (int kx = 0; kx < 3; ++kx)
              expected += static_cast<double>(taps[static_cast<std::size_t>(3 * ky + kx)]) *
                          src[k + static_cast<std::size_t>(ky * row_step + kx * col_step)];
          EXPECT_NEAR(sums[k], expected, 1e-5) << kernels->name << " dilation " << dilation << " k " << k;
        }
      }
    }
  }
}

TEST(ConvKernels, StrideTwoRowsReadOnlyTheEvenInputsUpToTheLastValidOne) {
  for (const ConvKernels* kernels : Builds()) {
    for (int out_cols = 1; out_cols <= 35; ++out_cols) {
      for (int offset : {-1, 0, 1, 3}) {
        const int begin = offset < 0 ? 1 : 0;
        // Exactly long enough for in[2 (out_cols - 1) + offset].
        const std::vector<float> in = Noise(static_cast<std::size_t>(2 * (out_cols - 1) + offset + 1), 6);
        std::vector<float> out = Noise(static_cast<std::size_t>(out_cols), 7);
        const std::vector<float> before = out;
        kernels->add_stride2_tap_row(in.data(), -0.61f, offset, out.data(), begin, out_cols);
        for (int x = 0; x < out_cols; ++x) {
          const double expected = x < begin ? before[static_cast<std::size_t>(x)]
                                            : before[static_cast<std::size_t>(x)] -
                                                  0.61 * in[static_cast<std::size_t>(2 * x + offset)];
          EXPECT_NEAR(out[static_cast<std::size_t>(x)], expected, 1e-6)
              << kernels->name << " cols " << out_cols << " offset " << offset << " x " << x;
        }
      }
    }
  }
}

}  // namespace
}  // namespace esdslam
