// Bilinear affine resampling (see resample.h): one row loop for every source kind, its samples 8 at
// a time with AVX2 gathers where the CPU has them, and a scalar loop with the same arithmetic.
#include "imaging/resample.h"

#include <immintrin.h>

#include <algorithm>
#include <cmath>
#include <type_traits>

#include "imaging/simd.h"

namespace fleetloc::imaging {
namespace {

// What is sampled: a float image, an 8-bit image, or the means of an 8-bit image's 2 × 2 squares.
enum class Source { kFloat, kBytes, kPairMeans };

template <Source kSource>
using Pixel = std::conditional_t<kSource == Source::kFloat, float, uchar>;

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

// The four bilinear neighbours of a sample whose top-left neighbour is at `at` (row stride
// `stride`): the scalar path's loads. A pair mean is the four bytes' sum (exact in float) times
// 1/4 (exact), so its order does not matter.
struct Quad {
  float p00, p01, p10, p11;
};

template <Source kSource>
inline Quad LoadQuad(const Pixel<kSource>* at, size_t stride) {
  if constexpr (kSource == Source::kPairMeans) {
    const uchar* r0 = at;
    const uchar* r1 = at + stride;
    const uchar* r2 = r1 + stride;
    const auto mean = [](int a, int b, int c, int d) {
      return static_cast<float>(a + b + c + d) * 0.25f;
    };
    return {mean(r0[0], r0[1], r1[0], r1[1]), mean(r0[1], r0[2], r1[1], r1[2]),
            mean(r1[0], r1[1], r2[0], r2[1]), mean(r1[1], r1[2], r2[1], r2[2])};
  } else {
    const auto* r1 = at + stride;
    return {static_cast<float>(at[0]), static_cast<float>(at[1]), static_cast<float>(r1[0]),
            static_cast<float>(r1[1])};
  }
}

// The four bilinear neighbours of eight samples at `index` (the top-left neighbour's pixel index)
// and `below` (index + stride), as floats; with kMasked, only the lanes of `mask` are loaded (a
// masked lane loads nothing and holds 0).
struct Neighbours {
  __m256 p00, p01, p10, p11;
};

// Eight 32-bit words of `base` at byte offsets `index` − `back` (the lanes of `mask` only when
// kMasked).
template <bool kMasked>
__attribute__((target("avx2"))) inline __m256i GatherWords(const uchar* base, __m256i index,
                                                           int back, __m256i mask) {
  const auto* words = reinterpret_cast<const int*>(base);
  const __m256i at = _mm256_sub_epi32(index, _mm256_set1_epi32(back));
  if constexpr (kMasked) {
    return _mm256_mask_i32gather_epi32(_mm256_setzero_si256(), words, at, mask, 1);
  } else {
    return _mm256_i32gather_epi32(words, at, 1);
  }
}

// Byte kByte (0 = the lowest) of each 32-bit lane.
template <int kByte>
__attribute__((target("avx2"))) inline __m256i ByteOf(__m256i words) {
  if constexpr (kByte == 3) {
    return _mm256_srli_epi32(words, 24);
  } else {
    return _mm256_and_si256(_mm256_srli_epi32(words, 8 * kByte), _mm256_set1_epi32(0xFF));
  }
}

// (a + b) / 4 as float (exact for sums of bytes).
__attribute__((target("avx2"))) inline __m256 QuarterOfSum(__m256i a, __m256i b) {
  return _mm256_mul_ps(_mm256_cvtepi32_ps(_mm256_add_epi32(a, b)), _mm256_set1_ps(0.25f));
}

template <bool kMasked, Source kSource>
__attribute__((target("avx2"))) inline Neighbours GatherNeighbours(const Pixel<kSource>* base,
                                                                   __m256i index, __m256i below,
                                                                   __m256i mask) {
  if constexpr (kSource == Source::kFloat) {
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
  } else if constexpr (kSource == Source::kBytes) {
    // One 32-bit load per row of neighbours, from two bytes before the sample: its top two bytes
    // are the pixel and its right neighbour. The caller guarantees index ≥ 2 in every loaded lane
    // (VectorRowFits), so the load starts inside the image; it ends at the right neighbour.
    const __m256i top = GatherWords<kMasked>(base, index, 2, mask);
    const __m256i bottom = GatherWords<kMasked>(base, below, 2, mask);
    return {_mm256_cvtepi32_ps(ByteOf<2>(top)), _mm256_cvtepi32_ps(ByteOf<3>(top)),
            _mm256_cvtepi32_ps(ByteOf<2>(bottom)), _mm256_cvtepi32_ps(ByteOf<3>(bottom))};
  } else {
    // Three rows of three bytes from one byte before the sample (index ≥ 1, VectorRowFits): bytes
    // 1–3 of each word. Each neighbour is the sum of a 2 × 2 square of them times 1/4.
    const __m256i stride = _mm256_sub_epi32(below, index);
    const __m256i r0 = GatherWords<kMasked>(base, index, 1, mask);
    const __m256i r1 = GatherWords<kMasked>(base, below, 1, mask);
    const __m256i r2 = GatherWords<kMasked>(base, _mm256_add_epi32(below, stride), 1, mask);
    const __m256i left = _mm256_add_epi32(ByteOf<1>(r0), ByteOf<1>(r1));
    const __m256i middle = _mm256_add_epi32(ByteOf<2>(r0), ByteOf<2>(r1));
    const __m256i right = _mm256_add_epi32(ByteOf<3>(r0), ByteOf<3>(r1));
    const __m256i left_low = _mm256_add_epi32(ByteOf<1>(r1), ByteOf<1>(r2));
    const __m256i middle_low = _mm256_add_epi32(ByteOf<2>(r1), ByteOf<2>(r2));
    const __m256i right_low = _mm256_add_epi32(ByteOf<3>(r1), ByteOf<3>(r2));
    return {QuarterOfSum(left, middle), QuarterOfSum(middle, right),
            QuarterOfSum(left_low, middle_low), QuarterOfSum(middle_low, right_low)};
  }
}

// Bilinear samples at output columns j .. j + 7 of a row; with kMasked, only the lanes of `mask`
// are loaded and stored. The arithmetic is the scalar path's, in the same order (the same floats).
template <bool kMasked, Source kSource>
__attribute__((target("avx2"))) inline void ResampleEightAvx2(const Pixel<kSource>* base,
                                                              __m256i stride, __m256 sx0,
                                                              __m256 sy0, __m256 a, __m256 c, int j,
                                                              __m256i mask, float* out) {
  const __m256 jj =
      _mm256_add_ps(_mm256_set1_ps(static_cast<float>(j)), _mm256_setr_ps(0, 1, 2, 3, 4, 5, 6, 7));
  const __m256 sx = _mm256_add_ps(sx0, _mm256_mul_ps(a, jj));
  const __m256 sy = _mm256_add_ps(sy0, _mm256_mul_ps(c, jj));
  const __m256i x0 = _mm256_cvttps_epi32(sx), y0 = _mm256_cvttps_epi32(sy);
  const __m256 ax = _mm256_sub_ps(sx, _mm256_cvtepi32_ps(x0));
  const __m256 ay = _mm256_sub_ps(sy, _mm256_cvtepi32_ps(y0));
  const __m256i index = _mm256_add_epi32(_mm256_mullo_epi32(y0, stride), x0);
  const auto [p00, p01, p10, p11] =
      GatherNeighbours<kMasked, kSource>(base, index, _mm256_add_epi32(index, stride), mask);
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
template <Source kSource>
__attribute__((target("avx2"))) void ResampleRowAvx2(const Pixel<kSource>* base, int stride,
                                                     float sx0, float sy0, float a, float c,
                                                     int begin, int end, float* out) {
  const __m256i stride_v = _mm256_set1_epi32(stride);
  const __m256 sx0_v = _mm256_set1_ps(sx0), sy0_v = _mm256_set1_ps(sy0);
  const __m256 a_v = _mm256_set1_ps(a), c_v = _mm256_set1_ps(c);
  int j = begin;
  for (; j + 8 <= end; j += 8) {
    ResampleEightAvx2<false, kSource>(base, stride_v, sx0_v, sy0_v, a_v, c_v, j, stride_v, out);
  }
  if (j < end) {
    ResampleEightAvx2<true, kSource>(base, stride_v, sx0_v, sy0_v, a_v, c_v, j,
                                     FirstLanesMask(end - j), out);
  }
}

// Whether the AVX2 path may sample a row's [begin, end) (j ↦ s0 + a·j in each axis, both ≥ 0):
// over bytes it loads from `back` bytes before each top-left neighbour (2, or 1 for pair means),
// which lies inside the image unless that neighbour is in the first row's first `back` columns.
// The coordinates are affine in j, so the range's ends bound them.
template <Source kSource>
bool VectorRowFits(float sx0, float sy0, float a, float c, int begin, int end) {
  if constexpr (kSource == Source::kFloat) {
    return true;
  } else {
    const float back = kSource == Source::kBytes ? 2.0f : 1.0f;
    const float last = static_cast<float>(end - 1), first = static_cast<float>(begin);
    return std::min(sy0 + c * first, sy0 + c * last) >= 1.0f ||
           std::min(sx0 + a * first, sx0 + a * last) >= back;
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

// `sampled`: the size of the image sampled (src's, or its pair means').
template <Source kSource>
void ResampleRows(const cv::Mat& src, cv::Size sampled, const cv::Matx23d& m, cv::Mat& dst) {
  // A margin of 1e-3 px keeps float rounding at the range ends inside the source.
  const float max_x = static_cast<float>(sampled.width - 1) - 1e-3f;
  const float max_y = static_cast<float>(sampled.height - 1) - 1e-3f;
  const float a = static_cast<float>(m(0, 0)), c = static_cast<float>(m(1, 0));
  const size_t stride = src.step[0] / sizeof(Pixel<kSource>);
  const Pixel<kSource>* base = src.ptr<Pixel<kSource>>(0);
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
    if (kHasAvx2 && VectorRowFits<kSource>(sx0, sy0, a, c, begin, end)) {
      ResampleRowAvx2<kSource>(base, static_cast<int>(stride), sx0, sy0, a, c, begin, end, out);
      continue;
    }
    for (int j = begin; j < end; ++j) {
      const float sx = sx0 + a * j, sy = sy0 + c * j;
      const int x0 = static_cast<int>(sx), y0 = static_cast<int>(sy);  // floor: both > 0
      const float ax = sx - x0, ay = sy - y0;
      const Quad q = LoadQuad<kSource>(base + y0 * stride + x0, stride);
      const float top = q.p00 + ax * (q.p01 - q.p00);
      const float bottom = q.p10 + ax * (q.p11 - q.p10);
      out[j] = top + ay * (bottom - top);
    }
  }
}

// Each pixel's mean with its neighbours `s` to the right, below and diagonally: a square of
// 2s × 2s pixels' mean from the means of its four s × s quarters (s = 1: of pixels).
template <typename T>
cv::Mat QuarterMeans(const cv::Mat& image, int s) {
  cv::Mat mean(image.rows - s, image.cols - s, CV_32F);
  for (int y = 0; y < mean.rows; ++y) {
    const T* top = image.ptr<T>(y);
    const T* bottom = image.ptr<T>(y + s);
    float* out = mean.ptr<float>(y);
    for (int x = 0; x < mean.cols; ++x) {
      out[x] = (static_cast<float>(top[x]) + static_cast<float>(top[x + s]) +
                static_cast<float>(bottom[x]) + static_cast<float>(bottom[x + s])) *
               0.25f;
    }
  }
  return mean;
}

}  // namespace

cv::Mat ResampleAffine(const cv::Mat& src, const cv::Matx23d& m, cv::Size size) {
  CV_Assert(src.type() == CV_8UC1 || src.type() == CV_32FC1);
  cv::Mat dst(size, CV_32F);
  if (src.type() == CV_8UC1) {
    ResampleRows<Source::kBytes>(src, src.size(), m, dst);
  } else {
    ResampleRows<Source::kFloat>(src, src.size(), m, dst);
  }
  return dst;
}

cv::Mat ResamplePairMeans(const cv::Mat& src, const cv::Matx23d& m, cv::Size size) {
  CV_Assert(src.type() == CV_8UC1 && src.rows >= 2 && src.cols >= 2);
  cv::Mat dst(size, CV_32F);
  ResampleRows<Source::kPairMeans>(src, {src.cols - 1, src.rows - 1}, m, dst);
  return dst;
}

cv::Mat BoxAverage(const cv::Mat& image, int k) {
  CV_Assert(image.type() == CV_8UC1 && k >= 1 && (k & (k - 1)) == 0 && image.rows >= k &&
            image.cols >= k);
  if (k == 1) {
    cv::Mat f;
    image.convertTo(f, CV_32F);
    return f;
  }
  cv::Mat mean = QuarterMeans<uchar>(image, 1);
  for (int s = 2; s < k; s *= 2) mean = QuarterMeans<float>(mean, s);
  return mean;
}

}  // namespace fleetloc::imaging
