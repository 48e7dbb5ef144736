// Hand-written small-patch kernels (see fast_patch.h for why): normalization and the texture grid;
// NccSurface is in ncc_surface.cpp, the resampling in resample.cpp.
#include "imaging/fast_patch.h"

#include <immintrin.h>

#include <algorithm>
#include <cmath>
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
