// The interior Gaussian blur (see gaussian_blur.h). Written by hand rather than calling
// cv::GaussianBlur because this Debian build's OpenCV runs float kernels at about 23 instructions
// a pixel for the polish's 11-tap blur (callgrind, 640×480 polished concrete under `all`: 13.6 M
// of the frame's 84 M), where 8-wide fused multiply–adds need about a third; the border
// handling OpenCV pays for is also not needed, as the caller cuts the margin.
#include "imaging/gaussian_blur.h"

#include <immintrin.h>

#include <array>
#include <opencv2/imgproc.hpp>
#include <utility>
#include <vector>

#include "imaging/simd.h"

namespace fleetloc::imaging {
namespace {

// Lanes x .. x + 7 of out[x] = Σ_k w[k]·in[k][x], the lanes at or beyond n masked off.
__attribute__((target("avx2,fma"))) inline __m256 MaskedSum(const float* const* in, const float* w,
                                                            int taps, int x, __m256i mask) {
  __m256 sum = _mm256_setzero_ps();
  for (int k = 0; k < taps; ++k) {
    sum = _mm256_fmadd_ps(_mm256_broadcast_ss(w + k), _mm256_maskload_ps(in[k] + x, mask), sum);
  }
  return sum;
}

// out[x] = Σ_k w[k]·in[k][x] for x < n: 32 lanes at a time (each weight loaded once for four
// vectors), then 8, then the last few under a mask.
__attribute__((target("avx2,fma"))) void WeightedSumAvx2(const float* const* in, const float* w,
                                                         int taps, int n, float* out) {
  int x = 0;
  for (; x + 32 <= n; x += 32) {
    __m256 a0 = _mm256_setzero_ps(), a1 = a0, a2 = a0, a3 = a0;
    for (int k = 0; k < taps; ++k) {
      const __m256 wk = _mm256_broadcast_ss(w + k);
      const float* row = in[k] + x;
      a0 = _mm256_fmadd_ps(wk, _mm256_loadu_ps(row), a0);
      a1 = _mm256_fmadd_ps(wk, _mm256_loadu_ps(row + 8), a1);
      a2 = _mm256_fmadd_ps(wk, _mm256_loadu_ps(row + 16), a2);
      a3 = _mm256_fmadd_ps(wk, _mm256_loadu_ps(row + 24), a3);
    }
    _mm256_storeu_ps(out + x, a0);
    _mm256_storeu_ps(out + x + 8, a1);
    _mm256_storeu_ps(out + x + 16, a2);
    _mm256_storeu_ps(out + x + 24, a3);
  }
  const __m256i all = _mm256_set1_epi32(-1);
  for (; x + 8 <= n; x += 8) _mm256_storeu_ps(out + x, MaskedSum(in, w, taps, x, all));
  if (x < n) {
    const __m256i mask = FirstLanesMask(n - x);
    _mm256_maskstore_ps(out + x, mask, MaskedSum(in, w, taps, x, mask));
  }
}

// The same sums for a kernel of kTaps taps known at compile time: the taps' weights and row
// pointers stay in registers and the tap loop unrolls (the tracker's patches are 40–60 px wide, so
// the generic loop's per-tap overhead was most of the cost). Same adds in the same order.
template <int kTaps>
__attribute__((target("avx2,fma"))) void WeightedSumFixedAvx2(const float* const* in,
                                                              const float* w, int n, float* out) {
  __m256 weight[kTaps];
  const float* row[kTaps];
  for (int k = 0; k < kTaps; ++k) weight[k] = _mm256_broadcast_ss(w + k), row[k] = in[k];
  int x = 0;
  for (; x + 16 <= n; x += 16) {
    __m256 a0 = _mm256_setzero_ps(), a1 = a0;
    for (int k = 0; k < kTaps; ++k) {
      a0 = _mm256_fmadd_ps(weight[k], _mm256_loadu_ps(row[k] + x), a0);
      a1 = _mm256_fmadd_ps(weight[k], _mm256_loadu_ps(row[k] + x + 8), a1);
    }
    _mm256_storeu_ps(out + x, a0);
    _mm256_storeu_ps(out + x + 8, a1);
  }
  for (; x < n; x += 8) {
    const __m256i mask = FirstLanesMask(n - x);
    __m256 a = _mm256_setzero_ps();
    for (int k = 0; k < kTaps; ++k) {
      a = _mm256_fmadd_ps(weight[k], _mm256_maskload_ps(row[k] + x, mask), a);
    }
    _mm256_maskstore_ps(out + x, mask, a);
  }
}

// The same sum without AVX2.
void WeightedSumPlain(const float* const* in, const float* w, int taps, int n, float* out) {
  for (int x = 0; x < n; ++x) {
    float sum = 0.0f;
    for (int k = 0; k < taps; ++k) sum += w[k] * in[k][x];
    out[x] = sum;
  }
}

using FixedWeightedSum = void (*)(const float* const*, const float*, int, float*);

// WeightedSumFixedAvx2 for radii 1 .. sizeof...(R) (3 .. 17 taps), indexed by radius − 1.
template <int... R>
constexpr std::array<FixedWeightedSum, sizeof...(R)> FixedWeightedSums(
    std::integer_sequence<int, R...>) {
  return {&WeightedSumFixedAvx2<2 * (R + 1) + 1>...};
}

void WeightedSum(const float* const* in, const float* w, int taps, int n, float* out) {
  static constexpr auto kFixed = FixedWeightedSums(std::make_integer_sequence<int, 8>());
  const int radius = taps / 2;
  if (!kHasAvx2Fma) {
    WeightedSumPlain(in, w, taps, n, out);
  } else if (radius >= 1 && radius <= static_cast<int>(kFixed.size())) {
    kFixed[radius - 1](in, w, n, out);
  } else {
    WeightedSumAvx2(in, w, taps, n, out);
  }
}

}  // namespace

cv::Mat GaussianBlurInterior(const cv::Mat& src, double sigma_px, int radius_px) {
  CV_Assert(src.type() == CV_32FC1 && sigma_px > 0 && radius_px >= 0);
  CV_Assert(src.cols > 2 * radius_px && src.rows > 2 * radius_px);
  const int taps = 2 * radius_px + 1;
  // The tracker blurs a few dozen small patches a frame with one kernel: the kernel and the
  // scratch row are kept between calls (per thread) rather than made again each time.
  thread_local cv::Mat kernel;
  thread_local double kernel_sigma = 0.0;
  if (kernel.rows != taps || kernel_sigma != sigma_px) {
    kernel = cv::getGaussianKernel(taps, sigma_px, CV_32F);
    kernel_sigma = sigma_px;
  }
  const float* w = kernel.ptr<float>(0);
  cv::Mat out(src.rows - 2 * radius_px, src.cols - 2 * radius_px, CV_32F);
  thread_local std::vector<float> column_sums;
  column_sums.resize(src.cols);
  std::vector<const float*> rows(taps), columns(taps);
  for (int k = 0; k < taps; ++k) columns[k] = column_sums.data() + k;
  for (int y = 0; y < out.rows; ++y) {
    for (int k = 0; k < taps; ++k) rows[k] = src.ptr<float>(y + k);
    WeightedSum(rows.data(), w, taps, src.cols, column_sums.data());
    WeightedSum(columns.data(), w, taps, out.cols, out.ptr<float>(y));
  }
  return out;
}

}  // namespace fleetloc::imaging
