// Run-time CPU feature checks and small helpers shared by the hand-written imaging kernels.
#pragma once

#include <immintrin.h>

namespace fleetloc::imaging {

// Hot kernels are compiled twice, for AVX2 and for the baseline, and picked at run time, so the
// build stays portable while a modern CPU gets 8-wide vectors.
#define FLEETLOC_VECTOR_CLONES __attribute__((target_clones("avx2", "default")))

inline const bool kHasAvx2 = __builtin_cpu_supports("avx2");
inline const bool kHasAvx2Fma = kHasAvx2 && __builtin_cpu_supports("fma");

// The sum of an 8-lane register's lanes.
__attribute__((target("avx2"))) inline float LaneSum(__m256 acc) {
  const __m128 half = _mm_add_ps(_mm256_castps256_ps128(acc), _mm256_extractf128_ps(acc, 1));
  const __m128 pair = _mm_add_ps(half, _mm_movehl_ps(half, half));
  return _mm_cvtss_f32(_mm_add_ss(pair, _mm_shuffle_ps(pair, pair, 1)));
}

// A lane mask for AVX2's masked loads and stores with the first n lanes (0–8) set.
__attribute__((target("avx2"))) inline __m256i FirstLanesMask(int n) {
  return _mm256_cmpgt_epi32(_mm256_set1_epi32(n), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
}

}  // namespace fleetloc::imaging
