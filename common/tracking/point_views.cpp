// The dense alignment's view sampling (see point_views.h). Each Gauss–Newton iteration samples
// every chosen pixel of its level (about 8,500 at 640×480's level 1); the scalar loop was a sixth
// of a dense frame's instructions at 640×480, most of it the per-pixel warp and bounds, which the
// AVX2 path does for eight pixels at once before the per-pixel bilinear reads.
#include "tracking/point_views.h"

#include <algorithm>

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

// Pixels [0, end) (a multiple of 8) eight at a time: the warp, the bounds and the fractions as
// vectors, the bilinear reads per pixel, the gradient's turn to frame axes as vectors again.
__attribute__((target("avx2"))) void SampleEightsAvx2(const PointWarp& w, const TexelBlock& block,
                                                      const Bounds& b, const PointSet& points,
                                                      size_t end, PointViews* views) {
  const __m256 l00 = _mm256_set1_ps(w.linear[0][0]), l01 = _mm256_set1_ps(w.linear[0][1]);
  const __m256 l10 = _mm256_set1_ps(w.linear[1][0]), l11 = _mm256_set1_ps(w.linear[1][1]);
  const __m256 ox = _mm256_set1_ps(w.offset[0]), oy = _mm256_set1_ps(w.offset[1]);
  const __m256 half = _mm256_set1_ps(0.5f), zero = _mm256_setzero_ps();
  const __m256 max_x = _mm256_set1_ps(b.max_x), max_y = _mm256_set1_ps(b.max_y);
  const __m256 origin_x = _mm256_set1_ps(b.origin_x), origin_y = _mm256_set1_ps(b.origin_y);
  const __m256i last_x0 = _mm256_set1_epi32(b.last_x0), last_y0 = _mm256_set1_epi32(b.last_y0);
  const __m256 t00 = _mm256_set1_ps(w.to_frame[0][0]), t01 = _mm256_set1_ps(w.to_frame[0][1]);
  const __m256 t10 = _mm256_set1_ps(w.to_frame[1][0]), t11 = _mm256_set1_ps(w.to_frame[1][1]);
  const __m256 scale = _mm256_set1_ps(w.scale), one = _mm256_set1_ps(1.0f);
  alignas(32) float fx[8], fy[8], s0[8], s1[8], s2[8];
  alignas(32) int x0[8], y0[8], inside[8];
  for (size_t i = 0; i < end; i += 8) {
    const __m256 u = _mm256_loadu_ps(points.u.data() + i), v = _mm256_loadu_ps(points.v.data() + i);
    const __m256 mx =
        _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(l00, u), _mm256_mul_ps(l01, v)), ox);
    const __m256 my =
        _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(l10, u), _mm256_mul_ps(l11, v)), oy);
    __m256 in = _mm256_and_ps(
        _mm256_and_ps(_mm256_cmp_ps(mx, half, _CMP_GE_OQ), _mm256_cmp_ps(my, half, _CMP_GE_OQ)),
        _mm256_and_ps(_mm256_cmp_ps(mx, max_x, _CMP_LE_OQ), _mm256_cmp_ps(my, max_y, _CMP_LE_OQ)));
    const __m256 bx = _mm256_sub_ps(_mm256_sub_ps(mx, half), origin_x);
    const __m256 by = _mm256_sub_ps(_mm256_sub_ps(my, half), origin_y);
    in = _mm256_and_ps(in, _mm256_and_ps(_mm256_cmp_ps(bx, zero, _CMP_GE_OQ),
                                         _mm256_cmp_ps(by, zero, _CMP_GE_OQ)));
    const __m256i ix = _mm256_cvttps_epi32(bx), iy = _mm256_cvttps_epi32(by);
    const __m256i beyond =
        _mm256_or_si256(_mm256_cmpgt_epi32(ix, last_x0), _mm256_cmpgt_epi32(iy, last_y0));
    in = _mm256_andnot_ps(_mm256_castsi256_ps(beyond), in);
    _mm256_store_ps(fx, _mm256_sub_ps(bx, _mm256_cvtepi32_ps(ix)));
    _mm256_store_ps(fy, _mm256_sub_ps(by, _mm256_cvtepi32_ps(iy)));
    _mm256_store_si256(reinterpret_cast<__m256i*>(x0), ix);
    _mm256_store_si256(reinterpret_cast<__m256i*>(y0), iy);
    _mm256_store_si256(reinterpret_cast<__m256i*>(inside), _mm256_castps_si256(in));
    for (int k = 0; k < 8; ++k) {
      float s[4] = {0.0f, 0.0f, 0.0f, 0.0f};
      if (inside[k] != 0) {
        Bilinear(block.texels->ptr<float>(y0[k]) + 4 * x0[k],
                 block.texels->ptr<float>(y0[k] + 1) + 4 * x0[k], fx[k], fy[k], s);
      }
      s0[k] = s[0];
      s1[k] = s[1];
      s2[k] = s[2];
    }
    const __m256 g1 = _mm256_load_ps(s1), g2 = _mm256_load_ps(s2);
    const __m256 gx =
        _mm256_mul_ps(_mm256_add_ps(_mm256_mul_ps(t00, g1), _mm256_mul_ps(t01, g2)), scale);
    const __m256 gy =
        _mm256_mul_ps(_mm256_add_ps(_mm256_mul_ps(t10, g1), _mm256_mul_ps(t11, g2)), scale);
    _mm256_storeu_ps(views->value.data() + i, _mm256_load_ps(s0));
    _mm256_storeu_ps(views->gx.data() + i, _mm256_and_ps(gx, in));
    _mm256_storeu_ps(views->gy.data() + i, _mm256_and_ps(gy, in));
    _mm256_storeu_ps(views->seen.data() + i, _mm256_and_ps(one, in));
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
  const size_t eights = path == SamplingPath::kFastest && imaging::kHasAvx2 ? n / 8 * 8 : 0;
  if (eights > 0) SampleEightsAvx2(warp, block, bounds, points, eights, views);
  for (size_t i = eights; i < n; ++i) {
    SampleOne(warp, block, bounds, points.u[i], points.v[i], i, views);
  }
}

}  // namespace fleetloc::tracking
