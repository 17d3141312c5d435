#include "semantic/conv_kernels.h"

#include <immintrin.h>

namespace esdslam {
namespace {

// ---- portable ----

void MultiplyAddPortable(const float* src, float weight, float* sums, std::size_t count) {
  for (std::size_t k = 0; k < count; ++k) sums[k] += weight * src[k];
}

void MultiplyAdd3x3Portable(const float* src, std::ptrdiff_t row_step, std::ptrdiff_t col_step, const float* taps,
                            float* sums, std::size_t count) {
  const float* r0 = src;
  const float* r1 = src + row_step;
  const float* r2 = src + 2 * row_step;
  const std::ptrdiff_t c1 = col_step, c2 = 2 * col_step;
  const float w0 = taps[0], w1 = taps[1], w2 = taps[2], w3 = taps[3], w4 = taps[4], w5 = taps[5], w6 = taps[6],
              w7 = taps[7], w8 = taps[8];
  for (std::size_t k = 0; k < count; ++k)
    sums[k] += w0 * r0[k] + w1 * r0[k + c1] + w2 * r0[k + c2] + w3 * r1[k] + w4 * r1[k + c1] + w5 * r1[k + c2] +
               w6 * r2[k] + w7 * r2[k + c1] + w8 * r2[k + c2];
}

void AddStride2TapRowPortable(const float* in, float weight, int offset, float* out, int begin, int end) {
  for (int x = begin; x < end; ++x) out[x] += weight * in[2 * x + offset];
}

// ---- AVX2 + FMA (only called when the CPU reports both) ----

__attribute__((target("avx2,fma"))) void MultiplyAddAvx2(const float* src, float weight, float* sums,
                                                         std::size_t count) {
  const __m256 w = _mm256_set1_ps(weight);
  std::size_t k = 0;
  for (; k + 8 <= count; k += 8)
    _mm256_storeu_ps(sums + k, _mm256_fmadd_ps(w, _mm256_loadu_ps(src + k), _mm256_loadu_ps(sums + k)));
  for (; k < count; ++k) sums[k] = __builtin_fmaf(weight, src[k], sums[k]);
}

// The sum of the nine taps is formed in the portable build's order (w0 r0 first), then added to
// the running sum.
__attribute__((target("avx2,fma"))) void MultiplyAdd3x3Avx2(const float* src, std::ptrdiff_t row_step,
                                                            std::ptrdiff_t col_step, const float* taps, float* sums,
                                                            std::size_t count) {
  const float* r0 = src;
  const float* r1 = src + row_step;
  const float* r2 = src + 2 * row_step;
  const std::ptrdiff_t c1 = col_step, c2 = 2 * col_step;
  __m256 w[9];
  for (int t = 0; t < 9; ++t) w[t] = _mm256_set1_ps(taps[t]);
  std::size_t k = 0;
  for (; k + 8 <= count; k += 8) {
    __m256 acc = _mm256_mul_ps(w[0], _mm256_loadu_ps(r0 + k));
    acc = _mm256_fmadd_ps(w[1], _mm256_loadu_ps(r0 + k + c1), acc);
    acc = _mm256_fmadd_ps(w[2], _mm256_loadu_ps(r0 + k + c2), acc);
    acc = _mm256_fmadd_ps(w[3], _mm256_loadu_ps(r1 + k), acc);
    acc = _mm256_fmadd_ps(w[4], _mm256_loadu_ps(r1 + k + c1), acc);
    acc = _mm256_fmadd_ps(w[5], _mm256_loadu_ps(r1 + k + c2), acc);
    acc = _mm256_fmadd_ps(w[6], _mm256_loadu_ps(r2 + k), acc);
    acc = _mm256_fmadd_ps(w[7], _mm256_loadu_ps(r2 + k + c1), acc);
    acc = _mm256_fmadd_ps(w[8], _mm256_loadu_ps(r2 + k + c2), acc);
    _mm256_storeu_ps(sums + k, _mm256_add_ps(_mm256_loadu_ps(sums + k), acc));
  }
  for (; k < count; ++k) {
    float acc = taps[0] * r0[k];
    acc = __builtin_fmaf(taps[1], r0[k + c1], acc);
    acc = __builtin_fmaf(taps[2], r0[k + c2], acc);
    acc = __builtin_fmaf(taps[3], r1[k], acc);
    acc = __builtin_fmaf(taps[4], r1[k + c1], acc);
    acc = __builtin_fmaf(taps[5], r1[k + c2], acc);
    acc = __builtin_fmaf(taps[6], r2[k], acc);
    acc = __builtin_fmaf(taps[7], r2[k + c1], acc);
    acc = __builtin_fmaf(taps[8], r2[k + c2], acc);
    sums[k] += acc;
  }
}

// Eight outputs from sixteen consecutive inputs: the even ones, in order.
__attribute__((target("avx2,fma"))) void AddStride2TapRowAvx2(const float* in, float weight, int offset, float* out,
                                                              int begin, int end) {
  const __m256 w = _mm256_set1_ps(weight);
  int x = begin;
  // The 16 floats read from in[2 x + offset] end at 2 x + offset + 15, at most the last index the
  // caller vouches for, 2 (end - 1) + offset, while x + 9 <= end.
  for (; x + 9 <= end; x += 8) {
    const float* p = in + 2 * x + offset;
    const __m256 lo = _mm256_loadu_ps(p), hi = _mm256_loadu_ps(p + 8);
    // [lo0 lo2 hi0 hi2 | lo4 lo6 hi4 hi6] -> [lo0 lo2 lo4 lo6 | hi0 hi2 hi4 hi6]
    const __m256 even_interleaved = _mm256_shuffle_ps(lo, hi, _MM_SHUFFLE(2, 0, 2, 0));
    const __m256 even =
        _mm256_castpd_ps(_mm256_permute4x64_pd(_mm256_castps_pd(even_interleaved), _MM_SHUFFLE(3, 1, 2, 0)));
    _mm256_storeu_ps(out + x, _mm256_fmadd_ps(w, even, _mm256_loadu_ps(out + x)));
  }
  for (; x < end; ++x) out[x] = __builtin_fmaf(weight, in[2 * x + offset], out[x]);
}

bool CpuHasAvx2Fma() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
}

}  // namespace

const ConvKernels& PortableConvKernels() {
  static const ConvKernels kernels{MultiplyAddPortable, MultiplyAdd3x3Portable, AddStride2TapRowPortable, "portable"};
  return kernels;
}

const ConvKernels* Avx2ConvKernels() {
  static const ConvKernels kernels{MultiplyAddAvx2, MultiplyAdd3x3Avx2, AddStride2TapRowAvx2, "avx2+fma"};
  static const bool available = CpuHasAvx2Fma();
  return available ? &kernels : nullptr;
}

const ConvKernels& BestConvKernels() {
  static const ConvKernels& best = Avx2ConvKernels() ? *Avx2ConvKernels() : PortableConvKernels();
  return best;
}

}  // namespace esdslam
