#pragma once
// The inner loops of the grouped convolution layer (semantic/grouped_conv_layer.h), in two
// builds: portable C++ (the compiler's baseline x86-64 vectorisation: 4 floats, no fused
// multiply-add) and AVX2 with FMA (8 floats, fused multiply-add), picked once at run time from
// what the CPU reports. The project is built without -march flags, so this is the one place the
// network's own layers use the wider instructions; OpenCV dispatches its own layers the same way.
//
// Both builds compute the same sums up to float rounding: FMA rounds once per multiply-add, the
// portable build twice; the order of the additions is the same.

#include <cstddef>

namespace esdslam {

struct ConvKernels {
  // sums[k] += weight * src[k], k in [0, count).
  void (*multiply_add)(const float* src, float weight, float* sums, std::size_t count);
  // sums[k] += sum over the taps (ky, kx) of taps[3 ky + kx] * src[k + ky row_step + kx col_step],
  // k in [0, count): one 3x3 kernel (dilation folded into the steps) over a run of padded rows.
  void (*multiply_add_3x3)(const float* src, std::ptrdiff_t row_step, std::ptrdiff_t col_step, const float* taps,
                           float* sums, std::size_t count);
  // out[x] += weight * in[2 x + offset], x in [begin, end); the caller keeps 2 x + offset inside
  // the input row for every x in the range (the zero padding is skipped by the caller).
  void (*add_stride2_tap_row)(const float* in, float weight, int offset, float* out, int begin, int end);
  const char* name;  // "portable" or "avx2+fma"
};

const ConvKernels& PortableConvKernels();
// The AVX2+FMA build, or nullptr when the CPU lacks AVX2 or FMA.
const ConvKernels* Avx2ConvKernels();
// What the layer uses: the AVX2+FMA build where the CPU has it, else the portable one.
const ConvKernels& BestConvKernels();

}  // namespace esdslam
