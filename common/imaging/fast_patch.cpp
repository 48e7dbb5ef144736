// Hand-written small-patch kernels (see fast_patch.h for why): normalization, resampling and
// the texture grid; NccSurface is in ncc_surface.cpp.
#include "imaging/fast_patch.h"

#include <immintrin.h>

#include <algorithm>
#include <cmath>
#include <type_traits>
#include <vector>

#include "imaging/simd.h"

namespace fleetloc::imaging {
namespace {

// Spare floats at the end of NormalizePatch's scratch rows, so that WindowSumsAvx2 may read and
// write whole vectors past a row's last pixel (the reads are of zeros).
constexpr int kRowSpare = 8;

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

// AddRow(in, +1) then AddRow(out, −1) in one pass over the column sums (the same adds in the
// same order).
FLEETLOC_VECTOR_CLONES
void SlideRow(const float* in, const float* out, float offset, float* sum, float* sum_sq, int n) {
  for (int x = 0; x < n; ++x) {
    const float v = in[x] - offset, u = out[x] - offset;
    sum[x] += v;
    sum_sq[x] += v * v;
    sum[x] += -u;
    sum_sq[x] += -u * u;
  }
}

// Window sums along a row, 8 at a time: sum[x] = Σ_{k<w} padded[x + k] (and the same of the
// squares), added in the order k = 0, 1, …, for every x < n rounded up to a multiple of 8 (the
// caller's rows have room: kRowSpare more floats). kW > 0 fixes w at compile time, so the tap
// loop unrolls (the tracker's windows are 5 and 7 px). Only called when the CPU has AVX2
// (checked at run time).
template <int kW>
__attribute__((target("avx2"))) int WindowSumsAvx2(const float* padded, const float* padded_sq,
                                                   int w, int n, float* sum, float* sq) {
  if constexpr (kW > 0) w = kW;
  int x = 0;
  for (; x < n; x += 8) {
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

int WindowSumsAvx2(const float* padded, const float* padded_sq, int w, int n, float* sum,
                   float* sq) {
  switch (w) {
    case 5:
      return WindowSumsAvx2<5>(padded, padded_sq, w, n, sum, sq);
    case 7:
      return WindowSumsAvx2<7>(padded, padded_sq, w, n, sum, sq);
    default:
      return WindowSumsAvx2<0>(padded, padded_sq, w, n, sum, sq);
  }
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

}  // namespace

cv::Mat NormalizePatch(const cv::Mat& patch, int window_px, float epsilon,
                       cv::Mat* local_variance) {
  CV_Assert(window_px >= 3 && window_px % 2 == 1);
  const cv::Mat f = AsFloat(patch);
  const int rows = f.rows, cols = f.cols, half = window_px / 2;
  std::vector<int> x_lo, x_hi, y_lo, y_hi;
  ClippedWindows(cols, half, x_lo, x_hi);
  ClippedWindows(rows, half, y_lo, y_hi);
  // The sums are taken of I − the patch's mean, whose squares are of the local variance's size
  // rather than of the grey level's: on a bright plain floor Σ I² − (Σ I)²/n cancels ~10⁶ down to
  // a few grey levels², below a float's resolution there.
  const float offset = static_cast<float>(cv::mean(f)[0]);
  // Column sums over the vertical window, updated row by row and kept between `half` zeros on
  // each side, so that the horizontal window sums need no clipping (the clipped pixel counts are
  // in inv_cols and inv_rows).
  std::vector<float> padded(cols + 2 * half + kRowSpare, 0.0f), padded_sq(padded.size(), 0.0f);
  float* col_sum = padded.data() + half;
  float* col_sq = padded_sq.data() + half;
  std::vector<float> sum(cols + kRowSpare), sq(cols + kRowSpare), inv_cols(cols);
  for (int x = 0; x < cols; ++x) {
    inv_cols[x] = 1.0f / static_cast<float>(x_hi[x] - x_lo[x]);
  }
  for (int y = 0; y < y_hi[0]; ++y) AddRow(f.ptr<float>(y), offset, col_sum, col_sq, cols, 1);
  cv::Mat out(f.size(), CV_32F);
  if (local_variance) local_variance->create(f.size(), CV_32F);
  for (int y = 0; y < rows; ++y) {
    const bool enters = y > 0 && y_hi[y] > y_hi[y - 1], leaves = y > 0 && y_lo[y] > y_lo[y - 1];
    if (enters && leaves) {
      SlideRow(f.ptr<float>(y_hi[y] - 1), f.ptr<float>(y_lo[y] - 1), offset, col_sum, col_sq, cols);
    } else if (enters) {
      AddRow(f.ptr<float>(y_hi[y] - 1), offset, col_sum, col_sq, cols, 1);
    } else if (leaves) {
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

// The four bilinear neighbours of eight samples at `index` (the top-left neighbour's pixel index)
// and `below` (index + stride), as floats; with kMasked, only the lanes of `mask` are loaded (a
// masked lane loads nothing and holds 0).
struct Neighbours {
  __m256 p00, p01, p10, p11;
};

template <bool kMasked>
__attribute__((target("avx2"))) inline Neighbours GatherNeighbours(const float* base, __m256i index,
                                                                   __m256i below, __m256i mask) {
  if constexpr (kMasked) {
    const __m256 valid = _mm256_castsi256_ps(mask), zero = _mm256_setzero_ps();
    return {_mm256_mask_i32gather_ps(zero, base, index, valid, 4),
            _mm256_mask_i32gather_ps(zero, base + 1, index, valid, 4),
            _mm256_mask_i32gather_ps(zero, base, below, valid, 4),
            _mm256_mask_i32gather_ps(zero, base + 1, below, valid, 4)};
  } else {
    return {_mm256_i32gather_ps(base, index, 4), _mm256_i32gather_ps(base + 1, index, 4),
            _mm256_i32gather_ps(base, below, 4), _mm256_i32gather_ps(base + 1, below, 4)};
  }
}

// Over 8-bit pixels, one 32-bit load per row of neighbours: the bytes at index − 2 … index + 1,
// whose top two bytes are the pixel and its right neighbour. Half the gathers of the float path,
// from a source a quarter the size (a 640×480 camera's polish view renders ~330 000 pixels from a
// ~1.4 MB float block, which outgrew the cache: the float path's gathers took a quarter of a
// frame's time on concrete under `all`). The caller guarantees index ≥ 2 in every loaded lane, so
// the load starts inside the image; it ends at the right neighbour, inside too.
template <bool kMasked>
__attribute__((target("avx2"))) inline Neighbours GatherNeighbours(const uchar* base, __m256i index,
                                                                   __m256i below, __m256i mask) {
  const __m256i two = _mm256_set1_epi32(2);
  const auto* words = reinterpret_cast<const int*>(base);
  __m256i top, bottom;
  if constexpr (kMasked) {
    const __m256i zero = _mm256_setzero_si256();
    top = _mm256_mask_i32gather_epi32(zero, words, _mm256_sub_epi32(index, two), mask, 1);
    bottom = _mm256_mask_i32gather_epi32(zero, words, _mm256_sub_epi32(below, two), mask, 1);
  } else {
    top = _mm256_i32gather_epi32(words, _mm256_sub_epi32(index, two), 1);
    bottom = _mm256_i32gather_epi32(words, _mm256_sub_epi32(below, two), 1);
  }
  const __m256i byte = _mm256_set1_epi32(0xFF);
  return {_mm256_cvtepi32_ps(_mm256_and_si256(_mm256_srli_epi32(top, 16), byte)),
          _mm256_cvtepi32_ps(_mm256_srli_epi32(top, 24)),
          _mm256_cvtepi32_ps(_mm256_and_si256(_mm256_srli_epi32(bottom, 16), byte)),
          _mm256_cvtepi32_ps(_mm256_srli_epi32(bottom, 24))};
}

// Bilinear samples at output columns j .. j + 7 of a row; with kMasked, only the lanes of `mask`
// are loaded and stored. The arithmetic is the scalar path's, in the same order (the same floats).
template <bool kMasked, typename Pixel>
__attribute__((target("avx2"))) inline void ResampleEightAvx2(const Pixel* base, __m256i stride,
                                                              __m256 sx0, __m256 sy0, __m256 a,
                                                              __m256 c, int j, __m256i mask,
                                                              float* out) {
  const __m256 jj =
      _mm256_add_ps(_mm256_set1_ps(static_cast<float>(j)), _mm256_setr_ps(0, 1, 2, 3, 4, 5, 6, 7));
  const __m256 sx = _mm256_add_ps(sx0, _mm256_mul_ps(a, jj));
  const __m256 sy = _mm256_add_ps(sy0, _mm256_mul_ps(c, jj));
  const __m256i x0 = _mm256_cvttps_epi32(sx), y0 = _mm256_cvttps_epi32(sy);
  const __m256 ax = _mm256_sub_ps(sx, _mm256_cvtepi32_ps(x0));
  const __m256 ay = _mm256_sub_ps(sy, _mm256_cvtepi32_ps(y0));
  const __m256i index = _mm256_add_epi32(_mm256_mullo_epi32(y0, stride), x0);
  const auto [p00, p01, p10, p11] =
      GatherNeighbours<kMasked>(base, index, _mm256_add_epi32(index, stride), mask);
  const __m256 top = _mm256_add_ps(p00, _mm256_mul_ps(ax, _mm256_sub_ps(p01, p00)));
  const __m256 bottom = _mm256_add_ps(p10, _mm256_mul_ps(ax, _mm256_sub_ps(p11, p10)));
  const __m256 value = _mm256_add_ps(top, _mm256_mul_ps(ay, _mm256_sub_ps(bottom, top)));
  if constexpr (kMasked) {
    _mm256_maskstore_ps(out + j, mask, value);
  } else {
    _mm256_storeu_ps(out + j, value);
  }
}

// Bilinear samples along one output row over [begin, end), 8 at a time with AVX2 gathers, the
// last partial 8 under a mask. Only called when the CPU has AVX2 (checked at run time).
template <typename Pixel>
__attribute__((target("avx2"))) void ResampleRowAvx2(const Pixel* base, int stride, float sx0,
                                                     float sy0, float a, float c, int begin,
                                                     int end, float* out) {
  const __m256i stride_v = _mm256_set1_epi32(stride);
  const __m256 sx0_v = _mm256_set1_ps(sx0), sy0_v = _mm256_set1_ps(sy0);
  const __m256 a_v = _mm256_set1_ps(a), c_v = _mm256_set1_ps(c);
  int j = begin;
  for (; j + 8 <= end; j += 8) {
    ResampleEightAvx2<false>(base, stride_v, sx0_v, sy0_v, a_v, c_v, j, stride_v, out);
  }
  if (j < end) {
    ResampleEightAvx2<true>(base, stride_v, sx0_v, sy0_v, a_v, c_v, j, FirstLanesMask(end - j),
                            out);
  }
}

// Whether the AVX2 path may sample a row's [begin, end) (j ↦ s0 + a·j in each axis, both ≥ 0):
// over 8-bit pixels it loads from two bytes before each top-left neighbour, which lies inside the
// image unless that neighbour is in the first row's first two columns. The coordinates are
// affine in j, so the range's ends bound them.
template <typename Pixel>
bool VectorRowFits(float sx0, float sy0, float a, float c, int begin, int end) {
  if constexpr (std::is_same_v<Pixel, float>) {
    return true;
  } else {
    const float last = static_cast<float>(end - 1), first = static_cast<float>(begin);
    return std::min(sy0 + c * first, sy0 + c * last) >= 1.0f ||
           std::min(sx0 + a * first, sx0 + a * last) >= 2.0f;
  }
}

// Whether every output pixel of `size` samples src inside [lo, max_x) × [lo, max_y): the map is
// affine, so the output's four corners decide it, with a margin beyond the per-row test's for the
// float rounding of the rows' coordinates (a few float steps at the source's size).
bool AllInside(const cv::Matx23d& m, cv::Size size, double max_x, double max_y) {
  const double spare = 1e-3 + 1e-6 * std::max(max_x, max_y), lo = 1e-3 + spare;
  for (const double j : {0.0, size.width - 1.0}) {
    for (const double i : {0.0, size.height - 1.0}) {
      const double sx = m(0, 0) * j + m(0, 1) * i + m(0, 2);
      const double sy = m(1, 0) * j + m(1, 1) * i + m(1, 2);
      if (!(sx >= lo && sx < max_x - spare && sy >= lo && sy < max_y - spare)) return false;
    }
  }
  return true;
}

template <typename Pixel>
void ResampleRows(const cv::Mat& src, const cv::Matx23d& m, cv::Mat& dst) {
  // A margin of 1e-3 px keeps float rounding at the range ends inside the source.
  const float max_x = static_cast<float>(src.cols - 1) - 1e-3f;
  const float max_y = static_cast<float>(src.rows - 1) - 1e-3f;
  const float a = static_cast<float>(m(0, 0)), c = static_cast<float>(m(1, 0));
  const size_t stride = src.step[0] / sizeof(Pixel);
  const Pixel* base = src.ptr<Pixel>(0);
  const bool all_inside = AllInside(m, dst.size(), max_x, max_y);
  for (int i = 0; i < dst.rows; ++i) {
    float* out = dst.ptr<float>(i);
    const float sx0 = static_cast<float>(m(0, 1) * i + m(0, 2));
    const float sy0 = static_cast<float>(m(1, 1) * i + m(1, 2));
    int begin = 0, end = dst.cols;
    if (!all_inside) {
      int bx, ex, by, ey;
      ValidRange(sx0, a, 1e-3f, max_x, dst.cols, &bx, &ex);
      ValidRange(sy0, c, 1e-3f, max_y, dst.cols, &by, &ey);
      begin = std::max(bx, by);
      end = std::max(begin, std::min(ex, ey));
      std::fill(out, out + begin, 0.0f);
      std::fill(out + end, out + dst.cols, 0.0f);
    }
    if (kHasAvx2 && VectorRowFits<Pixel>(sx0, sy0, a, c, begin, end)) {
      ResampleRowAvx2(base, static_cast<int>(stride), sx0, sy0, a, c, begin, end, out);
      continue;
    }
    for (int j = begin; j < end; ++j) {
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
