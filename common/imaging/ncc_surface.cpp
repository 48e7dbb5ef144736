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
        // Only the last block's loads are masked (a masked load costs more than a plain one).
        const __m256 values = b + 1 < NB ? _mm256_loadu_ps(v + tx + 8 * b)
                                         : _mm256_maskload_ps(v + tx + 8 * b, last_mask);
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
    cross.setTo(0.0f);
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

// Σ(v − offset) and Σ(v − offset)² over the first `n` values of a row, 8-wide.
__attribute__((target("avx2,fma"))) void FirstWindowSumsAvx2(const float* v, int n, float offset,
                                                             double* sum, double* sum_sq) {
  const __m256 shift = _mm256_set1_ps(offset);
  __m256 s = _mm256_setzero_ps(), q = _mm256_setzero_ps();
  int k = 0;
  for (; k + 8 <= n; k += 8) {
    const __m256 d = _mm256_sub_ps(_mm256_loadu_ps(v + k), shift);
    s = _mm256_add_ps(s, d);
    q = _mm256_fmadd_ps(d, d, q);
  }
  *sum = LaneSum(s);
  *sum_sq = LaneSum(q);
  for (; k < n; ++k) {
    const double d = v[k] - offset;
    *sum += d;
    *sum_sq += d * d;
  }
}

void FirstWindowSums(const float* v, int n, float offset, double* sum, double* sum_sq) {
  if (kHasAvx2Fma) return FirstWindowSumsAvx2(v, n, offset, sum, sum_sq);
  *sum = 0.0;
  *sum_sq = 0.0;
  for (int k = 0; k < n; ++k) {
    const double d = v[k] - offset;
    *sum += d;
    *sum_sq += d * d;
  }
}

// Σ(v − offset) and Σ(v − offset)² over the template's width `tw` at each of a window row's
// `cols` placements: the first window summed, then running in double (one add and one remove a
// placement). The offset keeps the sums small on bright images, where Σ v² would leave a float
// few digits for the window's spread.
void RowWindowSums(const float* v, int tw, int cols, float offset, double* sum, double* sum_sq) {
  double run = 0.0, run_sq = 0.0;
  FirstWindowSums(v, tw, offset, &run, &run_sq);
  sum[0] = run;
  sum_sq[0] = run_sq;
  for (int x = 1; x < cols; ++x) {
    const double in = v[x + tw - 1] - offset, out = v[x - 1] - offset;
    run += in - out;
    run_sq += in * in - out * out;
    sum[x] = run;
    sum_sq[x] = run_sq;
  }
}

// sum += add − remove (remove may be null), element-wise.
inline void Slide(const double* add, const double* remove, int n, double* sum) {
  if (remove == nullptr) {
    for (int i = 0; i < n; ++i) sum[i] += add[i];
  } else {
    for (int i = 0; i < n; ++i) sum[i] += add[i] - remove[i];
  }
}

// c = Σ t'·v / (√(Σ(v − v̄)²) · ‖t'‖) from the window sums `sum` and `sum_sq` of n_pixels values;
// where |c| reaches the spread (rounding, or a flat window), as `rule` says.
inline void DivideBySpread(const double* sum, const double* sum_sq, int n, double n_pixels,
                           double t_norm, SpreadRule rule, float* c) {
  for (int i = 0; i < n; ++i) {
    const double spread = std::sqrt(std::max(0.0, sum_sq[i] - sum[i] * sum[i] / n_pixels)) * t_norm;
    if (rule == SpreadRule::kZeroWhenFlat) {
      c[i] = spread > 1e-9 ? static_cast<float>(c[i] / spread) : 0.0f;
    } else if (std::abs(c[i]) < spread) {
      c[i] = static_cast<float>(c[i] / spread);
    } else {
      c[i] = std::abs(c[i]) < spread * 1.125 ? (c[i] > 0 ? 1.0f : -1.0f) : 0.0f;
    }
  }
}

}  // namespace

// Per window row the sums over the template's width, then running down the template's height,
// all in double, of v − `offset`. The scratch rows are reused across calls (thread_local: the
// tracker calls this a few thousand times a frame, most for a handful of placements).
FLEETLOC_VECTOR_CLONES
void NormalizeBySpread(const cv::Mat& window, cv::Size templ, float offset, double templ_norm,
                       SpreadRule rule, cv::Mat& cross) {
  const int th = templ.height, tw = templ.width;
  const int cols = cross.cols;
  thread_local std::vector<double> scratch;
  scratch.resize(2 * static_cast<size_t>(window.rows + 1) * cols);
  double* seg = scratch.data();
  double* seg_sq = seg + static_cast<size_t>(window.rows) * cols;
  double* sum = seg_sq + static_cast<size_t>(window.rows) * cols;
  double* sum_sq = sum + cols;
  for (int y = 0; y < window.rows; ++y) {
    RowWindowSums(window.ptr<float>(y), tw, cols, offset, &seg[y * cols], &seg_sq[y * cols]);
  }
  std::fill(sum, sum + 2 * cols, 0.0);
  for (int y = 0; y < th; ++y) {
    Slide(&seg[y * cols], nullptr, cols, sum);
    Slide(&seg_sq[y * cols], nullptr, cols, sum_sq);
  }
  const double n = static_cast<double>(th) * tw;
  for (int y = 0; y < cross.rows; ++y) {
    if (y > 0) {
      Slide(&seg[(y + th - 1) * cols], &seg[(y - 1) * cols], cols, sum);
      Slide(&seg_sq[(y + th - 1) * cols], &seg_sq[(y - 1) * cols], cols, sum_sq);
    }
    DivideBySpread(sum, sum_sq, cols, n, templ_norm, rule, cross.ptr<float>(y));
  }
}

namespace {

// The zero-mean template t' = t − t̄ into `t0`, with t̄ and ‖t'‖ summed in double lanes (by hand:
// OpenCV's cv::mean and `templ - mean` cost several times the arithmetic on a 48² template in
// their per-call set-up).
__attribute__((target("avx2,fma"))) void ZeroMeanAvx2(const cv::Mat& templ, cv::Mat& t0,
                                                      double* mean, double* norm) {
  const int full = templ.cols & ~3;
  __m256d acc = _mm256_setzero_pd();
  double tail = 0.0;
  for (int y = 0; y < templ.rows; ++y) {
    const float* t = templ.ptr<float>(y);
    for (int x = 0; x < full; x += 4)
      acc = _mm256_add_pd(acc, _mm256_cvtps_pd(_mm_loadu_ps(t + x)));
    for (int x = full; x < templ.cols; ++x) tail += t[x];
  }
  alignas(32) double lanes[4];
  _mm256_store_pd(lanes, acc);
  *mean = (lanes[0] + lanes[1] + lanes[2] + lanes[3] + tail) / static_cast<double>(templ.total());
  const __m256d m = _mm256_set1_pd(*mean);
  __m256d acc_sq = _mm256_setzero_pd();
  double tail_sq = 0.0;
  for (int y = 0; y < templ.rows; ++y) {
    const float* t = templ.ptr<float>(y);
    float* d = t0.ptr<float>(y);
    for (int x = 0; x < full; x += 4) {
      const __m128 r = _mm256_cvtpd_ps(_mm256_sub_pd(_mm256_cvtps_pd(_mm_loadu_ps(t + x)), m));
      _mm_storeu_ps(d + x, r);
      const __m256d rd = _mm256_cvtps_pd(r);
      acc_sq = _mm256_fmadd_pd(rd, rd, acc_sq);
    }
    for (int x = full; x < templ.cols; ++x) {
      d[x] = static_cast<float>(t[x] - *mean);
      tail_sq += static_cast<double>(d[x]) * d[x];
    }
  }
  _mm256_store_pd(lanes, acc_sq);
  *norm = std::sqrt(lanes[0] + lanes[1] + lanes[2] + lanes[3] + tail_sq);
}

cv::Mat ZeroMean(const cv::Mat& templ, double* mean, double* norm) {
  cv::Mat t0(templ.size(), CV_32F);
  if (kHasAvx2Fma) {
    ZeroMeanAvx2(templ, t0, mean, norm);
  } else {
    *mean = cv::mean(templ)[0];
    cv::subtract(templ, cv::Scalar(*mean), t0);
    *norm = std::sqrt(t0.dot(t0));
  }
  return t0;
}

}  // namespace

cv::Mat CrossCorrelationSums(const cv::Mat& window, const cv::Mat& templ) {
  CV_Assert(window.type() == CV_32F && templ.type() == CV_32F);
  CV_Assert(window.cols >= templ.cols && window.rows >= templ.rows);
  cv::Mat cross(window.rows - templ.rows + 1, window.cols - templ.cols + 1, CV_32F);
  CrossSums(window, templ, cross);
  return cross;
}

double CrossCorrelationSumsCost(cv::Size window, cv::Size templ) {
  const int rows = window.height - templ.height + 1, cols = window.width - templ.width + 1;
  // Up to 15 placements a row: each placement along the template's 8-wide chunks; more: blocks
  // of 8 placements for each template pixel (CrossSums).
  const double per_row =
      cols < 16 ? cols * std::ceil(templ.width / 8.0) : std::ceil(cols / 8.0) * templ.width;
  return per_row * templ.height * rows;
}

cv::Mat NccSurface(const cv::Mat& window, const cv::Mat& templ) {
  CV_Assert(window.type() == CV_32F && templ.type() == CV_32F);
  const int th = templ.rows, tw = templ.cols;
  const int rows = window.rows - th + 1, cols = window.cols - tw + 1;
  CV_Assert(rows > 0 && cols > 0);
  // Zero-mean template: Σ t'·(v − v̄) = Σ t'·v, so only one product sum per position is needed.
  double mean = 0.0, t_norm = 0.0;
  const cv::Mat t0 = ZeroMean(templ, &mean, &t_norm);
  cv::Mat cross(rows, cols, CV_32F);
  CrossSums(window, t0, cross);
  NormalizeBySpread(window, templ.size(), static_cast<float>(mean), t_norm,
                    SpreadRule::kZeroWhenFlat, cross);
  return cross;
}

}  // namespace fleetloc::imaging
