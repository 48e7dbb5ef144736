// NccSurface (fast_patch.h): the normalized cross-correlation of a small template at every
// placement in a small window, with the products summed by hand-written AVX2 kernels (see
// fast_patch.h for why not cv::matchTemplate).
#include <immintrin.h>

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <utility>
#include <vector>

#include "imaging/fast_patch.h"
#include "imaging/simd.h"

namespace fleetloc::imaging {
namespace {

// A float dot product with 8-wide AVX2 multiply-adds (the compiler may not reorder a float sum
// into SIMD lanes by itself).
__attribute__((target("avx2,fma"))) float DotAvx2(const float* a, const float* b, int n) {
  __m256 acc0 = _mm256_setzero_ps(), acc1 = _mm256_setzero_ps();
  int i = 0;
  for (; i + 16 <= n; i += 16) {
    acc0 = _mm256_fmadd_ps(_mm256_loadu_ps(a + i), _mm256_loadu_ps(b + i), acc0);
    acc1 = _mm256_fmadd_ps(_mm256_loadu_ps(a + i + 8), _mm256_loadu_ps(b + i + 8), acc1);
  }
  for (; i + 8 <= n; i += 8) {
    acc0 = _mm256_fmadd_ps(_mm256_loadu_ps(a + i), _mm256_loadu_ps(b + i), acc0);
  }
  float s = LaneSum(_mm256_add_ps(acc0, acc1));
  for (; i < n; ++i) s += a[i] * b[i];
  return s;
}

// Without AVX2: Eigen's SIMD reduction for the baseline instruction set.
float Dot(const float* a, const float* b, int n) {
  if (kHasAvx2Fma) return DotAvx2(a, b, n);
  return Eigen::Map<const Eigen::VectorXf>(a, n).dot(Eigen::Map<const Eigen::VectorXf>(b, n));
}

inline void Axpy(float a, const float* x, float* y, int n) {
  for (int i = 0; i < n; ++i) y[i] += a * x[i];
}

// Σ t·v per placement with many placements per row: vectorized across placements (the loops
// are inlined into each clone, so the AVX2 clone vectorizes 8-wide without a call per row).
FLEETLOC_VECTOR_CLONES
void CrossSumsAcrossPlacements(const cv::Mat& window, const cv::Mat& t0, cv::Mat& cross) {
  const int th = t0.rows, tw = t0.cols, rows = cross.rows, cols = cross.cols;
  for (int ty = 0; ty < th; ++ty) {
    const float* trow = t0.ptr<float>(ty);
    for (int y = 0; y < rows; ++y) {
      const float* vrow = window.ptr<float>(y + ty);
      float* c = cross.ptr<float>(y);
      for (int tx = 0; tx < tw; ++tx) Axpy(trow[tx], vrow + tx, c, cols);
    }
  }
}

// Σ t·v for NB blocks of 8 placements of one row, kept in registers: per template pixel one
// broadcast weight, and one load and one multiply-add per block (NB independent chains). The
// last block may be partial (`last_mask`): its loads and store are masked, so nothing is read or
// written past the row's placements. Adds in the same order as CrossSumsAcrossPlacements.
template <int NB>
__attribute__((target("avx2,fma"))) void CrossSumsBlocksAvx2(const cv::Mat& window,
                                                             const cv::Mat& t0, int y, int x0,
                                                             __m256i last_mask, float* c) {
  const __m256i all = _mm256_set1_epi32(-1);
  __m256 acc[NB];
  for (int b = 0; b < NB; ++b) acc[b] = _mm256_setzero_ps();
  for (int ty = 0; ty < t0.rows; ++ty) {
    const float* trow = t0.ptr<float>(ty);
    const float* v = window.ptr<float>(y + ty) + x0;
    for (int tx = 0; tx < t0.cols; ++tx) {
      const __m256 weight = _mm256_broadcast_ss(trow + tx);
      for (int b = 0; b < NB; ++b) {
        const __m256 values = _mm256_maskload_ps(v + tx + 8 * b, b + 1 < NB ? all : last_mask);
        acc[b] = _mm256_fmadd_ps(weight, values, acc[b]);
      }
    }
  }
  for (int b = 0; b < NB; ++b)
    _mm256_maskstore_ps(c + x0 + 8 * b, b + 1 < NB ? all : last_mask, acc[b]);
}

// Σ t·v per placement with many placements per row, up to 32 placements at a time in registers.
__attribute__((target("avx2,fma"))) void CrossSumsAcrossPlacementsAvx2(const cv::Mat& window,
                                                                       const cv::Mat& t0,
                                                                       cv::Mat& cross) {
  const int cols = cross.cols;
  for (int y = 0; y < cross.rows; ++y) {
    float* c = cross.ptr<float>(y);
    for (int x0 = 0; x0 < cols; x0 += 32) {
      const int n = std::min(32, cols - x0), blocks = (n + 7) / 8, tail = n - 8 * (blocks - 1);
      const __m256i mask = FirstLanesMask(tail);
      switch (blocks) {
        case 1:
          CrossSumsBlocksAvx2<1>(window, t0, y, x0, mask, c);
          break;
        case 2:
          CrossSumsBlocksAvx2<2>(window, t0, y, x0, mask, c);
          break;
        case 3:
          CrossSumsBlocksAvx2<3>(window, t0, y, x0, mask, c);
          break;
        default:
          CrossSumsBlocksAvx2<4>(window, t0, y, x0, mask, c);
          break;
      }
    }
  }
}

// Σ t·v for the NP placements of row y, each an 8-wide multiply-add loop along the whole template
// (masked tail for widths that are not a multiple of 8). Each load of the template serves all NP
// placements, whose partial sums stay in registers.
template <int NP>
__attribute__((target("avx2,fma"))) void CrossSumsRowAlongTemplateAvx2(const cv::Mat& window,
                                                                       const cv::Mat& t0, int y,
                                                                       float* c) {
  const int full = t0.cols & ~7, tail = t0.cols - full;
  const __m256i mask = FirstLanesMask(tail);
  __m256 acc[NP];
  for (int p = 0; p < NP; ++p) acc[p] = _mm256_setzero_ps();
  for (int ty = 0; ty < t0.rows; ++ty) {
    const float* t = t0.ptr<float>(ty);
    const float* v = window.ptr<float>(y + ty);
    for (int i = 0; i < full; i += 8) {
      const __m256 weights = _mm256_loadu_ps(t + i);
      for (int p = 0; p < NP; ++p) {
        acc[p] = _mm256_fmadd_ps(weights, _mm256_loadu_ps(v + p + i), acc[p]);
      }
    }
    if (tail > 0) {
      const __m256 weights = _mm256_maskload_ps(t + full, mask);
      for (int p = 0; p < NP; ++p) {
        acc[p] = _mm256_fmadd_ps(weights, _mm256_maskload_ps(v + p + full, mask), acc[p]);
      }
    }
  }
  for (int p = 0; p < NP; ++p) c[p] = LaneSum(acc[p]);
}

using RowAlongTemplate = void (*)(const cv::Mat&, const cv::Mat&, int, float*);

template <int... N>
constexpr std::array<RowAlongTemplate, sizeof...(N)> RowAlongTemplateKernels(
    std::integer_sequence<int, N...>) {
  return {&CrossSumsRowAlongTemplateAvx2<N + 1>...};
}

// Σ t·v per placement with few placements (1–15 a row): one kernel per count, so that the
// placements' partial sums are registers.
void CrossSumsAlongTemplateAvx2(const cv::Mat& window, const cv::Mat& t0, cv::Mat& cross) {
  static constexpr auto kKernels = RowAlongTemplateKernels(std::make_integer_sequence<int, 15>());
  CV_Assert(cross.cols >= 1 && cross.cols <= static_cast<int>(kKernels.size()));
  const RowAlongTemplate kernel = kKernels[cross.cols - 1];
  for (int y = 0; y < cross.rows; ++y) kernel(window, t0, y, cross.ptr<float>(y));
}

// Σ t·v for every placement of the template (rows × cols placements).
void CrossSums(const cv::Mat& window, const cv::Mat& t0, cv::Mat& cross) {
  if (cross.cols >= 16 && kHasAvx2Fma) {
    CrossSumsAcrossPlacementsAvx2(window, t0, cross);
  } else if (cross.cols >= 16) {
    CrossSumsAcrossPlacements(window, t0, cross);
  } else if (kHasAvx2Fma) {
    CrossSumsAlongTemplateAvx2(window, t0, cross);
  } else {
    for (int y = 0; y < cross.rows; ++y) {
      float* c = cross.ptr<float>(y);
      for (int x = 0; x < cross.cols; ++x) {
        float s = 0.0f;
        for (int ty = 0; ty < t0.rows; ++ty) {
          s += Dot(t0.ptr<float>(ty), window.ptr<float>(y + ty) + x, t0.cols);
        }
        c[x] = s;
      }
    }
  }
}

}  // namespace

cv::Mat NccSurface(const cv::Mat& window, const cv::Mat& templ) {
  CV_Assert(window.type() == CV_32F && templ.type() == CV_32F);
  const int th = templ.rows, tw = templ.cols;
  const int rows = window.rows - th + 1, cols = window.cols - tw + 1;
  CV_Assert(rows > 0 && cols > 0);
  // Zero-mean template: Σ t'·(v − v̄) = Σ t'·v, so only one product sum per position is needed.
  const double n = static_cast<double>(th) * tw;
  cv::Mat t0 = templ - cv::mean(templ)[0];
  const double t_norm = std::sqrt(t0.dot(t0));
  cv::Mat cross = cv::Mat::zeros(rows, cols, CV_32F);
  CrossSums(window, t0, cross);
  // Sum and sum of squares of the window under each placement: per row, the sums over each
  // tw-wide segment (one SIMD sum, then sliding), then sliding th rows down.
  std::vector<float> seg(static_cast<size_t>(window.rows) * cols), seg_sq(seg.size());
  for (int y = 0; y < window.rows; ++y) {
    const float* v = window.ptr<float>(y);
    const Eigen::Map<const Eigen::ArrayXf> first(v, tw);
    float run = first.sum(), run_sq = first.square().sum();
    for (int x = 0; x < cols; ++x) {
      if (x > 0) {
        run += v[x + tw - 1] - v[x - 1];
        run_sq += v[x + tw - 1] * v[x + tw - 1] - v[x - 1] * v[x - 1];
      }
      seg[y * cols + x] = run;
      seg_sq[y * cols + x] = run_sq;
    }
  }
  for (int x = 0; x < cols; ++x) {
    double s = 0.0, s2 = 0.0;
    for (int y = 0; y < th; ++y) {
      s += seg[y * cols + x];
      s2 += seg_sq[y * cols + x];
    }
    for (int y = 0; y < rows; ++y) {
      if (y > 0) {
        s += seg[(y + th - 1) * cols + x] - seg[(y - 1) * cols + x];
        s2 += seg_sq[(y + th - 1) * cols + x] - seg_sq[(y - 1) * cols + x];
      }
      const double denominator = std::sqrt(std::max(0.0, s2 - s * s / n)) * t_norm;
      float& c = cross.at<float>(y, x);
      c = denominator > 1e-9 ? static_cast<float>(c / denominator) : 0.0f;
    }
  }
  return cross;
}

}  // namespace fleetloc::imaging
