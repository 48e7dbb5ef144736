// The dense alignment's view sampling (see point_views.h). Each Gauss–Newton iteration samples
// every chosen pixel of its level (about 8,500 at 640×480's level 1); the scalar loop was a sixth
// of a dense frame's instructions at 640×480. The AVX2 path places eight pixels at once and reads
// their bilinear neighbours two pixels to a vector: 89 → 37 µs for a 640×480 camera's level 1
// (docs/benchmarks.md, session 52).
#include "tracking/point_views.h"

#include <algorithm>
#include <cstdint>

#include "imaging/simd.h"

namespace fleetloc::tracking {
namespace {

// The bilinear value and gradient (out[0..2]; out[3] scratch) between the texels at r0, r0 + 4
// (top row) and r1, r1 + 4 (bottom row), at fractions fx, fy: the channels together, in one
// 4-lane vector. The same arithmetic in the same order in both paths (the same floats).
inline void Bilinear(const float* r0, const float* r1, float fx, float fy, float out[4]) {
  const __m128 a = _mm_loadu_ps(r0), b = _mm_loadu_ps(r0 + 4);
  const __m128 c = _mm_loadu_ps(r1), d = _mm_loadu_ps(r1 + 4);
  const __m128 wx = _mm_set1_ps(fx);
  const __m128 top = _mm_add_ps(a, _mm_mul_ps(wx, _mm_sub_ps(b, a)));
  const __m128 bottom = _mm_add_ps(c, _mm_mul_ps(wx, _mm_sub_ps(d, c)));
  _mm_storeu_ps(out, _mm_add_ps(top, _mm_mul_ps(_mm_set1_ps(fy), _mm_sub_ps(bottom, top))));
}

// The block's bounds as floats and ints, once per call.
struct Bounds {
  float max_x, max_y, origin_x, origin_y;
  int last_x0, last_y0;
  explicit Bounds(const TexelBlock& block)
      : max_x(block.level_size.width - 0.5f),
        max_y(block.level_size.height - 0.5f),
        origin_x(static_cast<float>(block.origin.x)),
        origin_y(static_cast<float>(block.origin.y)),
        last_x0(block.texels->cols - 2),
        last_y0(block.texels->rows - 2) {}
};

// One pixel's view, stored at index i.
inline void SampleOne(const PointWarp& w, const TexelBlock& block, const Bounds& b, float u,
                      float v, size_t i, PointViews* views) {
  const float mx = (w.linear[0][0] * u + w.linear[0][1] * v) + w.offset[0];
  const float my = (w.linear[1][0] * u + w.linear[1][1] * v) + w.offset[1];
  views->value[i] = views->gx[i] = views->gy[i] = views->seen[i] = 0.0f;
  if (!(mx >= 0.5f && my >= 0.5f && mx <= b.max_x && my <= b.max_y)) return;
  const float bx = mx - 0.5f - b.origin_x, by = my - 0.5f - b.origin_y;
  if (!(bx >= 0.0f && by >= 0.0f)) return;
  const int x0 = static_cast<int>(bx), y0 = static_cast<int>(by);  // the floor, as bx, by ≥ 0
  if (x0 > b.last_x0 || y0 > b.last_y0) return;
  float s[4];
  Bilinear(block.texels->ptr<float>(y0) + 4 * x0, block.texels->ptr<float>(y0 + 1) + 4 * x0,
           bx - static_cast<float>(x0), by - static_cast<float>(y0), s);
  views->value[i] = s[0];
  views->gx[i] = (w.to_frame[0][0] * s[1] + w.to_frame[0][1] * s[2]) * w.scale;
  views->gy[i] = (w.to_frame[1][0] * s[1] + w.to_frame[1][1] * s[2]) * w.scale;
  views->seen[i] = 1.0f;
}

// Eight pixels' places in the block: which lie inside it (`in`, all bits set), their bilinear
// fractions and their top-left texel's float index (0 where outside, so every read stays in the
// block).
struct EightPlaces {
  __m256 in, fx, fy;
  __m256i index;
};

__attribute__((target("avx2"))) EightPlaces PlaceEight(const PointWarp& w, const Bounds& b,
                                                       int stride, __m256 u, __m256 v) {
  const __m256 half = _mm256_set1_ps(0.5f), zero = _mm256_setzero_ps();
  const __m256 mx = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(_mm256_set1_ps(w.linear[0][0]), u),
                                                _mm256_mul_ps(_mm256_set1_ps(w.linear[0][1]), v)),
                                  _mm256_set1_ps(w.offset[0]));
  const __m256 my = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(_mm256_set1_ps(w.linear[1][0]), u),
                                                _mm256_mul_ps(_mm256_set1_ps(w.linear[1][1]), v)),
                                  _mm256_set1_ps(w.offset[1]));
  __m256 in = _mm256_and_ps(
      _mm256_and_ps(_mm256_cmp_ps(mx, half, _CMP_GE_OQ), _mm256_cmp_ps(my, half, _CMP_GE_OQ)),
      _mm256_and_ps(_mm256_cmp_ps(mx, _mm256_set1_ps(b.max_x), _CMP_LE_OQ),
                    _mm256_cmp_ps(my, _mm256_set1_ps(b.max_y), _CMP_LE_OQ)));
  const __m256 bx = _mm256_sub_ps(_mm256_sub_ps(mx, half), _mm256_set1_ps(b.origin_x));
  const __m256 by = _mm256_sub_ps(_mm256_sub_ps(my, half), _mm256_set1_ps(b.origin_y));
  in = _mm256_and_ps(
      in, _mm256_and_ps(_mm256_cmp_ps(bx, zero, _CMP_GE_OQ), _mm256_cmp_ps(by, zero, _CMP_GE_OQ)));
  const __m256i ix = _mm256_cvttps_epi32(bx), iy = _mm256_cvttps_epi32(by);
  const __m256i beyond = _mm256_or_si256(_mm256_cmpgt_epi32(ix, _mm256_set1_epi32(b.last_x0)),
                                         _mm256_cmpgt_epi32(iy, _mm256_set1_epi32(b.last_y0)));
  in = _mm256_andnot_ps(_mm256_castsi256_ps(beyond), in);
  const __m256i index =
      _mm256_add_epi32(_mm256_mullo_epi32(iy, _mm256_set1_epi32(stride)), _mm256_slli_epi32(ix, 2));
  return {in, _mm256_sub_ps(bx, _mm256_cvtepi32_ps(ix)), _mm256_sub_ps(by, _mm256_cvtepi32_ps(iy)),
          _mm256_and_si256(index, _mm256_castps_si256(in))};
}

// The four floats at data + at[lo] (low half) and data + at[hi] (high half).
__attribute__((target("avx2"))) inline __m256 LoadPair(const float* data, const int* at, int lo,
                                                       int hi, int offset) {
  return _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(data + at[lo] + offset)),
                              _mm_loadu_ps(data + at[hi] + offset), 1);
}

// The bilinear value and gradient of pixels k (low half) and k + 4 (high half), all four channels
// at once: Bilinear's arithmetic, in the same order.
__attribute__((target("avx2"))) inline __m256 BilinearPair(const float* data, int stride,
                                                           const int* at, const EightPlaces& e,
                                                           int k) {
  const __m256i lanes = _mm256_setr_epi32(k, k, k, k, k + 4, k + 4, k + 4, k + 4);
  const __m256 wx = _mm256_permutevar8x32_ps(e.fx, lanes);
  const __m256 wy = _mm256_permutevar8x32_ps(e.fy, lanes);
  const __m256 a = LoadPair(data, at, k, k + 4, 0), b = LoadPair(data, at, k, k + 4, 4);
  const __m256 c = LoadPair(data, at, k, k + 4, stride);
  const __m256 d = LoadPair(data, at, k, k + 4, stride + 4);
  const __m256 top = _mm256_add_ps(a, _mm256_mul_ps(wx, _mm256_sub_ps(b, a)));
  const __m256 bottom = _mm256_add_ps(c, _mm256_mul_ps(wx, _mm256_sub_ps(d, c)));
  return _mm256_add_ps(top, _mm256_mul_ps(wy, _mm256_sub_ps(bottom, top)));
}

// Pixels [0, end) (a multiple of 8) eight at a time: their places as vectors (PlaceEight), the
// bilinear reads two pixels to a vector, transposed to value and gradient vectors, the gradient
// turned to frame axes as vectors. Needs a block of at least 2 × 2 texels.
__attribute__((target("avx2"))) void SampleEightsAvx2(const PointWarp& w, const TexelBlock& block,
                                                      const Bounds& b, const PointSet& points,
                                                      size_t end, PointViews* views) {
  const float* data = block.texels->ptr<float>();
  const int stride = static_cast<int>(block.texels->step1());
  const __m256 t00 = _mm256_set1_ps(w.to_frame[0][0]), t01 = _mm256_set1_ps(w.to_frame[0][1]);
  const __m256 t10 = _mm256_set1_ps(w.to_frame[1][0]), t11 = _mm256_set1_ps(w.to_frame[1][1]);
  const __m256 scale = _mm256_set1_ps(w.scale), one = _mm256_set1_ps(1.0f);
  alignas(32) int at[8];
  for (size_t i = 0; i < end; i += 8) {
    const EightPlaces e = PlaceEight(w, b, stride, _mm256_loadu_ps(points.u.data() + i),
                                     _mm256_loadu_ps(points.v.data() + i));
    _mm256_store_si256(reinterpret_cast<__m256i*>(at), e.index);
    const __m256 r0 = BilinearPair(data, stride, at, e, 0),
                 r1 = BilinearPair(data, stride, at, e, 1);
    const __m256 r2 = BilinearPair(data, stride, at, e, 2),
                 r3 = BilinearPair(data, stride, at, e, 3);
    // Each register holds (value, d/dx, d/dy, 0) of pixels k and k + 4: transposed per half.
    const __m256 lo01 = _mm256_unpacklo_ps(r0, r1), lo23 = _mm256_unpacklo_ps(r2, r3);
    const __m256 hi01 = _mm256_unpackhi_ps(r0, r1), hi23 = _mm256_unpackhi_ps(r2, r3);
    const __m256 value = _mm256_shuffle_ps(lo01, lo23, _MM_SHUFFLE(1, 0, 1, 0));
    const __m256 g1 = _mm256_shuffle_ps(lo01, lo23, _MM_SHUFFLE(3, 2, 3, 2));
    const __m256 g2 = _mm256_shuffle_ps(hi01, hi23, _MM_SHUFFLE(1, 0, 1, 0));
    const __m256 gx =
        _mm256_mul_ps(_mm256_add_ps(_mm256_mul_ps(t00, g1), _mm256_mul_ps(t01, g2)), scale);
    const __m256 gy =
        _mm256_mul_ps(_mm256_add_ps(_mm256_mul_ps(t10, g1), _mm256_mul_ps(t11, g2)), scale);
    _mm256_storeu_ps(views->value.data() + i, _mm256_and_ps(value, e.in));
    _mm256_storeu_ps(views->gx.data() + i, _mm256_and_ps(gx, e.in));
    _mm256_storeu_ps(views->gy.data() + i, _mm256_and_ps(gy, e.in));
    _mm256_storeu_ps(views->seen.data() + i, _mm256_and_ps(one, e.in));
  }
}

}  // namespace

void SamplePointViews(const PointWarp& warp, const TexelBlock& block, const PointSet& points,
                      PointViews* views, SamplingPath path) {
  CV_Assert(block.texels->type() == CV_32FC4);
  const size_t n = points.size();
  for (std::vector<float>* a : {&views->value, &views->gx, &views->gy, &views->seen}) {
    a->resize(n);
  }
  const Bounds bounds(block);
  const bool vector = path == SamplingPath::kFastest && imaging::kHasAvx2 &&
                      block.texels->cols >= 2 && block.texels->rows >= 2 &&
                      block.texels->isContinuous() &&
                      block.texels->total() < static_cast<size_t>(INT32_MAX / 4);
  const size_t eights = vector ? n / 8 * 8 : 0;
  if (eights > 0) SampleEightsAvx2(warp, block, bounds, points, eights, views);
  for (size_t i = eights; i < n; ++i) {
    SampleOne(warp, block, bounds, points.u[i], points.v[i], i, views);
  }
}

}  // namespace fleetloc::tracking
