// Hand-written small-patch kernels (see fast_patch.h for why).
#include "imaging/fast_patch.h"

#include <immintrin.h>

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <type_traits>
#include <utility>
#include <vector>

namespace fleetloc::imaging {
namespace {

// Hot kernels are compiled twice, for AVX2 and for the baseline, and picked at run time, so the
// build stays portable while a modern CPU gets 8-wide vectors.
#define FLEETLOC_VECTOR_CLONES __attribute__((target_clones("avx2", "default")))

const bool kHasAvx2 = __builtin_cpu_supports("avx2");
const bool kHasAvx2Fma = kHasAvx2 && __builtin_cpu_supports("fma");

cv::Mat AsFloat(const cv::Mat& m) {
  if (m.type() == CV_32F) return m;
  cv::Mat f;
  m.convertTo(f, CV_32F);
  return f;
}

// Window [lo, hi) of each index, clipped to [0, n).
void ClippedWindows(int n, int half, std::vector<int>& lo, std::vector<int>& hi) {
  lo.resize(n);
  hi.resize(n);
  for (int i = 0; i < n; ++i) {
    lo[i] = std::max(0, i - half);
    hi[i] = std::min(n, i + half + 1);
  }
}

// Adds (sign 1) or takes away (sign −1) one row of I − offset to the column sums.
FLEETLOC_VECTOR_CLONES
void AddRow(const float* in, float offset, float* sum, float* sum_sq, int n, float sign) {
  for (int x = 0; x < n; ++x) {
    const float v = in[x] - offset;
    sum[x] += sign * v;
    sum_sq[x] += sign * v * v;
  }
}

// Window sums along a row, 8 at a time: sum[x] = Σ_{k<w} padded[x + k] (and the same of the
// squares), added in the order k = 0, 1, …; returns the first x it did not do. Only called when
// the CPU has AVX2 (checked at run time).
__attribute__((target("avx2"))) int WindowSumsAvx2(const float* padded, const float* padded_sq,
                                                   int w, int n, float* sum, float* sq) {
  int x = 0;
  for (; x + 8 <= n; x += 8) {
    __m256 s = _mm256_loadu_ps(padded + x), q = _mm256_loadu_ps(padded_sq + x);
    for (int k = 1; k < w; ++k) {
      s = _mm256_add_ps(s, _mm256_loadu_ps(padded + x + k));
      q = _mm256_add_ps(q, _mm256_loadu_ps(padded_sq + x + k));
    }
    _mm256_storeu_ps(sum + x, s);
    _mm256_storeu_ps(sq + x, q);
  }
  return x;
}

// Each pixel's window sum is taken directly rather than as the difference of two running
// prefix sums: a prefix along a 256-px tile row of 7 rows' squares reaches ~10⁸, where a float's
// step is 8, so the difference lost whole grey levels² of a plain floor's local variance; and
// the prefix loop is one serial chain of dependent adds.
void WindowSums(const float* padded, const float* padded_sq, int w, int n, float* sum, float* sq) {
  int x = kHasAvx2 ? WindowSumsAvx2(padded, padded_sq, w, n, sum, sq) : 0;
  for (; x < n; ++x) {
    float s = padded[x], q = padded_sq[x];
    for (int k = 1; k < w; ++k) {
      s += padded[x + k];
      q += padded_sq[x + k];
    }
    sum[x] = s;
    sq[x] = q;
  }
}

// One row's output from the window sums of I − offset: mean = Σ/n, variance = max(0, Σ²/n −
// mean²) (stored when `variance` is not null) and (I − offset − mean) / (σ + ε).
FLEETLOC_VECTOR_CLONES
void NormalizeRowFromSums(const float* in, float offset, const float* sum, const float* sq,
                          const float* inv_cols, float inv_rows, float epsilon, float* out,
                          float* variance, int n) {
  for (int x = 0; x < n; ++x) {
    const float inv_n = inv_cols[x] * inv_rows;
    const float mean = sum[x] * inv_n;
    const float v = std::max(0.0f, sq[x] * inv_n - mean * mean);
    out[x] = (in[x] - offset - mean) / (std::sqrt(v) + epsilon);
    if (variance) variance[x] = v;
  }
}

// The sum of an 8-lane register's lanes.
__attribute__((target("avx2"))) inline float LaneSum(__m256 acc) {
  const __m128 half = _mm_add_ps(_mm256_castps256_ps128(acc), _mm256_extractf128_ps(acc, 1));
  const __m128 pair = _mm_add_ps(half, _mm_movehl_ps(half, half));
  return _mm_cvtss_f32(_mm_add_ss(pair, _mm_shuffle_ps(pair, pair, 1)));
}

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
      alignas(32) int mask_bits[8];
      for (int i = 0; i < 8; ++i) mask_bits[i] = i < tail ? -1 : 0;
      const __m256i mask = _mm256_load_si256(reinterpret_cast<const __m256i*>(mask_bits));
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
  alignas(32) int mask_bits[8];
  for (int i = 0; i < 8; ++i) mask_bits[i] = i < tail ? -1 : 0;
  const __m256i mask = _mm256_load_si256(reinterpret_cast<const __m256i*>(mask_bits));
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

cv::Mat NormalizePatch(const cv::Mat& patch, int window_px, float epsilon,
                       cv::Mat* local_variance) {
  CV_Assert(window_px >= 3 && window_px % 2 == 1);
  const cv::Mat f = AsFloat(patch);
  const int rows = f.rows, cols = f.cols, half = window_px / 2;
  std::vector<int> y_lo, y_hi;
  ClippedWindows(rows, half, y_lo, y_hi);
  // The sums are taken of I − the patch's mean, whose squares are of the local variance's size
  // rather than of the grey level's: on a bright plain floor Σ I² − (Σ I)²/n cancels ~10⁶ down to
  // a few grey levels², below a float's resolution there.
  const float offset = static_cast<float>(cv::mean(f)[0]);
  // Column sums over the vertical window, updated row by row and kept between `half` zeros on
  // each side, so that the horizontal window sums need no clipping (the clipped pixel counts are
  // in inv_cols and inv_rows).
  std::vector<float> padded(cols + 2 * half, 0.0f), padded_sq(cols + 2 * half, 0.0f);
  float* col_sum = padded.data() + half;
  float* col_sq = padded_sq.data() + half;
  std::vector<float> sum(cols), sq(cols), inv_cols(cols);
  for (int x = 0; x < cols; ++x) {
    inv_cols[x] = 1.0f / static_cast<float>(std::min(cols, x + half + 1) - std::max(0, x - half));
  }
  for (int y = 0; y < y_hi[0]; ++y) AddRow(f.ptr<float>(y), offset, col_sum, col_sq, cols, 1);
  cv::Mat out(f.size(), CV_32F);
  if (local_variance) local_variance->create(f.size(), CV_32F);
  for (int y = 0; y < rows; ++y) {
    if (y > 0 && y_hi[y] > y_hi[y - 1]) {
      AddRow(f.ptr<float>(y_hi[y] - 1), offset, col_sum, col_sq, cols, 1);
    }
    if (y > 0 && y_lo[y] > y_lo[y - 1]) {
      AddRow(f.ptr<float>(y_lo[y] - 1), offset, col_sum, col_sq, cols, -1);
    }
    WindowSums(padded.data(), padded_sq.data(), window_px, cols, sum.data(), sq.data());
    const float inv_rows = 1.0f / static_cast<float>(y_hi[y] - y_lo[y]);
    NormalizeRowFromSums(f.ptr<float>(y), offset, sum.data(), sq.data(), inv_cols.data(), inv_rows,
                         epsilon, out.ptr<float>(y),
                         local_variance ? local_variance->ptr<float>(y) : nullptr, cols);
  }
  return out;
}

namespace {

// The range [j_begin, j_end) of j ≥ 0 for which lo ≤ s0 + a·j < hi (all j when a = 0 and s0 fits).
void ValidRange(float s0, float a, float lo, float hi, int n, int* j_begin, int* j_end) {
  if (a == 0.0f) {
    const bool inside = s0 >= lo && s0 < hi;
    *j_begin = 0;
    *j_end = inside ? n : 0;
    return;
  }
  double first = (lo - s0) / a, last = (hi - s0) / a;
  if (a < 0) std::swap(first, last);
  *j_begin = std::clamp(static_cast<int>(std::ceil(first)), 0, n);
  *j_end = std::clamp(static_cast<int>(std::ceil(last)), *j_begin, n);
}

// Bilinear samples of a float image along one output row, 8 at a time with AVX2 gathers; returns
// the first j it did not do. Only called when the CPU has AVX2 (checked at run time).
__attribute__((target("avx2"))) int ResampleRowAvx2(const float* base, int stride, float sx0,
                                                    float sy0, float a, float c, int begin, int end,
                                                    float* out) {
  const __m256 lane = _mm256_setr_ps(0, 1, 2, 3, 4, 5, 6, 7);
  const __m256i stride_v = _mm256_set1_epi32(stride);
  int j = begin;
  for (; j + 8 <= end; j += 8) {
    const __m256 jj = _mm256_add_ps(_mm256_set1_ps(static_cast<float>(j)), lane);
    const __m256 sx = _mm256_add_ps(_mm256_set1_ps(sx0), _mm256_mul_ps(_mm256_set1_ps(a), jj));
    const __m256 sy = _mm256_add_ps(_mm256_set1_ps(sy0), _mm256_mul_ps(_mm256_set1_ps(c), jj));
    const __m256i x0 = _mm256_cvttps_epi32(sx), y0 = _mm256_cvttps_epi32(sy);
    const __m256 ax = _mm256_sub_ps(sx, _mm256_cvtepi32_ps(x0));
    const __m256 ay = _mm256_sub_ps(sy, _mm256_cvtepi32_ps(y0));
    const __m256i index = _mm256_add_epi32(_mm256_mullo_epi32(y0, stride_v), x0);
    const __m256i below = _mm256_add_epi32(index, stride_v);
    const __m256 p00 = _mm256_i32gather_ps(base, index, 4);
    const __m256 p01 = _mm256_i32gather_ps(base + 1, index, 4);
    const __m256 p10 = _mm256_i32gather_ps(base, below, 4);
    const __m256 p11 = _mm256_i32gather_ps(base + 1, below, 4);
    const __m256 top = _mm256_add_ps(p00, _mm256_mul_ps(ax, _mm256_sub_ps(p01, p00)));
    const __m256 bottom = _mm256_add_ps(p10, _mm256_mul_ps(ax, _mm256_sub_ps(p11, p10)));
    _mm256_storeu_ps(out + j, _mm256_add_ps(top, _mm256_mul_ps(ay, _mm256_sub_ps(bottom, top))));
  }
  return j;
}

template <typename Pixel>
void ResampleRows(const cv::Mat& src, const cv::Matx23d& m, cv::Mat& dst) {
  // A margin of 1e-3 px keeps float rounding at the range ends inside the source.
  const float max_x = static_cast<float>(src.cols - 1) - 1e-3f;
  const float max_y = static_cast<float>(src.rows - 1) - 1e-3f;
  const float a = static_cast<float>(m(0, 0)), c = static_cast<float>(m(1, 0));
  const size_t stride = src.step[0] / sizeof(Pixel);
  const Pixel* base = src.ptr<Pixel>(0);
  for (int i = 0; i < dst.rows; ++i) {
    float* out = dst.ptr<float>(i);
    const float sx0 = static_cast<float>(m(0, 1) * i + m(0, 2));
    const float sy0 = static_cast<float>(m(1, 1) * i + m(1, 2));
    int bx, ex, by, ey;
    ValidRange(sx0, a, 1e-3f, max_x, dst.cols, &bx, &ex);
    ValidRange(sy0, c, 1e-3f, max_y, dst.cols, &by, &ey);
    const int begin = std::max(bx, by), end = std::max(begin, std::min(ex, ey));
    std::fill(out, out + begin, 0.0f);
    std::fill(out + end, out + dst.cols, 0.0f);
    int j = begin;
    if constexpr (std::is_same_v<Pixel, float>) {
      if (kHasAvx2) {
        j = ResampleRowAvx2(base, static_cast<int>(stride), sx0, sy0, a, c, begin, end, out);
      }
    }
    for (; j < end; ++j) {
      const float sx = sx0 + a * j, sy = sy0 + c * j;
      const int x0 = static_cast<int>(sx), y0 = static_cast<int>(sy);  // floor: both > 0
      const float ax = sx - x0, ay = sy - y0;
      const Pixel* r0 = base + y0 * stride + x0;
      const Pixel* r1 = r0 + stride;
      const float top = r0[0] + ax * (static_cast<float>(r0[1]) - r0[0]);
      const float bottom = r1[0] + ax * (static_cast<float>(r1[1]) - r1[0]);
      out[j] = top + ay * (bottom - top);
    }
  }
}

}  // namespace

cv::Mat ResampleAffine(const cv::Mat& src, const cv::Matx23d& m, cv::Size size) {
  CV_Assert(src.type() == CV_8UC1 || src.type() == CV_32FC1);
  cv::Mat dst(size, CV_32F);
  if (src.type() == CV_8UC1) {
    ResampleRows<uchar>(src, m, dst);
  } else {
    ResampleRows<float>(src, m, dst);
  }
  return dst;
}

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

cv::Mat TextureScoreGrid(const cv::Mat& gray, int step_px, int window_px) {
  CV_Assert(gray.type() == CV_8UC1 && step_px >= 1 && window_px >= 3 && window_px % 2 == 1);
  const int rows = gray.rows / step_px - 1, cols = gray.cols / step_px - 1, h = window_px / 2;
  cv::Mat score(rows, cols, CV_32F, cv::Scalar(0));
  for (int gy = 0; gy < rows; ++gy) {
    const int cy = (gy + 1) * step_px;
    for (int gx = 0; gx < cols; ++gx) {
      const int cx = (gx + 1) * step_px;
      if (cy - h < 1 || cx - h < 1 || cy + h + 1 >= gray.rows || cx + h + 1 >= gray.cols) continue;
      float a = 0, b = 0, c = 0;
      for (int y = cy - h; y <= cy + h; ++y) {
        const uchar* up = gray.ptr<uchar>(y - 1);
        const uchar* mid = gray.ptr<uchar>(y);
        const uchar* down = gray.ptr<uchar>(y + 1);
        for (int x = cx - h; x <= cx + h; ++x) {
          const float dx = 0.5f * (mid[x + 1] - mid[x - 1]);
          const float dy = 0.5f * (down[x] - up[x]);
          a += dx * dx;
          b += dx * dy;
          c += dy * dy;
        }
      }
      const float n = static_cast<float>(window_px * window_px);
      a /= n;
      b /= n;
      c /= n;
      const float half_diff = 0.5f * (a - c);
      score.at<float>(gy, gx) =
          std::max(0.0f, 0.5f * (a + c) - std::sqrt(half_diff * half_diff + b * b));
    }
  }
  return score;
}

}  // namespace fleetloc::imaging
