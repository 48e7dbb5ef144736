// The robust normal equations over a level's chosen pixels (LinearizePoints, see
// dense_linearization.h): the sparse levels of the dense alignment, summed block by block in
// vectorized lanes, as LinearizeWholeFrame sums the frame row by row.
#include <algorithm>
#include <cmath>

#include "tracking/dense_linearization.h"

namespace fleetloc::tracking {
namespace {

// The sums of one score block: the normal equations' upper triangle, the score Σ w·r·J, the
// correlation sums, the pixels with weight > 0 and the inliers (weight > 0.5).
enum PointSum {
  kH00,
  kH01,
  kH02,
  kH11,
  kH12,
  kH22,
  kS0,
  kS1,
  kS2,
  kSw,
  kSt,
  kSv,
  kStt,
  kSvv,
  kStv,
  kUsed,
  kInliers,
  kPointSums
};

// A PointSet's and its PointViews' arrays as plain pointers, for the vectorizer.
struct PointArrays {
  const float* __restrict t;
  const float* __restrict v;
  const float* __restrict seen;
  const float* __restrict gx;
  const float* __restrict gy;
  const float* __restrict du0;
  const float* __restrict dv0;
};

// One pixel's terms added to lane sums `acc[sum * stride]`. Branch-free so the lanes vectorize.
inline void AddPoint(const PointArrays& p, int i, float gain, float inv_cutoff_sq, float* acc,
                     int stride) {
  const float t = p.t[i], v = p.v[i], seen = p.seen[i];
  const float r = t - gain * v;
  const float a = r * r * inv_cutoff_sq;
  const float b = 0.5f * ((1.0f - a) + std::abs(1.0f - a));  // max(0, 1 − a)
  const float w = b * b * seen;
  const float used = (0.5f + 0.5f * std::copysign(1.0f, 1.0f - a)) * seen;
  const float inlier = (0.5f + 0.5f * std::copysign(1.0f, 0.29289322f - a)) * seen;  // w > 0.5
  // J for q = (qx, qy, qθ) in camera_ground axes: frame x is ground −y, frame y is ground −x.
  const float gx = gain * p.gx[i], gy = gain * p.gy[i];
  const float j0 = -gy, j1 = -gx, j2 = gx * p.dv0[i] - gy * p.du0[i];
  const float wj0 = w * j0, wj1 = w * j1, wj2 = w * j2;
  acc[kH00 * stride] += wj0 * j0, acc[kH01 * stride] += wj0 * j1, acc[kH02 * stride] += wj0 * j2;
  acc[kH11 * stride] += wj1 * j1, acc[kH12 * stride] += wj1 * j2, acc[kH22 * stride] += wj2 * j2;
  acc[kS0 * stride] += wj0 * r, acc[kS1 * stride] += wj1 * r, acc[kS2 * stride] += wj2 * r;
  acc[kSw * stride] += w, acc[kSt * stride] += w * t, acc[kSv * stride] += w * v;
  acc[kStt * stride] += w * t * t, acc[kSvv * stride] += w * v * v, acc[kStv * stride] += w * t * v;
  acc[kUsed * stride] += used, acc[kInliers * stride] += inlier;
}

// The sums over pixels [begin, end): eight lanes of independent sums, so the compiler vectorizes
// the lanes (a plain reduction it may not reorder); built for AVX2 as well as the baseline, the
// loader picks the best the CPU has. Float: a block holds at most a few hundred pixels.
__attribute__((target_clones("avx2", "default"))) void SumBlock(const PointArrays& p, int begin,
                                                                int end, float gain,
                                                                float inv_cutoff_sq, float* sums) {
  constexpr int kLanes = 8;
  alignas(32) float lanes[kPointSums][kLanes] = {};
  int i = begin;
  for (; i + kLanes <= end; i += kLanes) {
    for (int k = 0; k < kLanes; ++k) {
      AddPoint(p, i + k, gain, inv_cutoff_sq, &lanes[0][k], kLanes);
    }
  }
  for (int s = 0; s < kPointSums; ++s) sums[s] = 0.0f;
  for (; i < end; ++i) AddPoint(p, i, gain, inv_cutoff_sq, sums, 1);
  for (int s = 0; s < kPointSums; ++s) {
    for (int k = 0; k < kLanes; ++k) sums[s] += lanes[s][k];
  }
}

// The least-squares contrast of the seen pixels' frame values against their view's.
double StartingGain(const PointSet& p, const PointViews& view) {
  double stv = 0.0, svv = 0.0;  // unseen views are 0: they add nothing
  for (size_t i = 0; i < p.size(); ++i) {
    stv += p.value[i] * view.value[i], svv += view.value[i] * view.value[i];
  }
  return LeastSquaresGain(stv, svv);
}

// 1.4826 × the median absolute residual t − gain·v over the seen pixels (at least 1e-3).
double ResidualScale(const PointSet& p, const PointViews& view, double gain) {
  std::vector<float> magnitudes;
  magnitudes.reserve(p.size());
  const float g = static_cast<float>(gain);
  for (size_t i = 0; i < p.size(); ++i) {
    if (view.seen[i] != 0.0f) magnitudes.push_back(std::abs(p.value[i] - g * view.value[i]));
  }
  if (magnitudes.empty()) return 1e-3;
  const auto mid = magnitudes.begin() + magnitudes.size() / 2;
  std::nth_element(magnitudes.begin(), mid, magnitudes.end());
  return std::max(1e-3, 1.4826 * *mid);
}

}  // namespace

Linearization LinearizePoints(const PointSet& p, const PointViews& view, double tukey_c,
                              double sigma, double gain) {
  Linearization lin;
  lin.points = static_cast<int>(std::count(view.seen.begin(), view.seen.end(), 1.0f));
  if (lin.points < 3) return lin;
  lin.gain = gain > 0 ? gain : StartingGain(p, view);
  lin.sigma = sigma > 0 ? sigma : ResidualScale(p, view, lin.gain);
  const float inv_cutoff_sq = static_cast<float>(1.0 / (tukey_c * tukey_c * lin.sigma * lin.sigma));
  std::vector<Eigen::Vector3d> block_scores(kScoreBlocks * kScoreBlocks, Eigen::Vector3d::Zero());
  std::vector<int> block_counts(kScoreBlocks * kScoreBlocks, 0);
  CorrelationSums c;
  double inliers = 0;
  const PointArrays arrays{p.value.data(), view.value.data(), view.seen.data(), view.gx.data(),
                           view.gy.data(), p.du0.data(),      p.dv0.data()};
  for (int b = 0; b < kScoreBlocks * kScoreBlocks; ++b) {
    if (p.block_start[b + 1] <= p.block_start[b]) continue;
    float s[kPointSums];
    SumBlock(arrays, p.block_start[b], p.block_start[b + 1], static_cast<float>(lin.gain),
             inv_cutoff_sq, s);
    lin.h(0, 0) += s[kH00], lin.h(0, 1) += s[kH01], lin.h(0, 2) += s[kH02];
    lin.h(1, 1) += s[kH11], lin.h(1, 2) += s[kH12], lin.h(2, 2) += s[kH22];
    c.sw += s[kSw], c.st += s[kSt], c.sv += s[kSv];
    c.stt += s[kStt], c.svv += s[kSvv], c.stv += s[kStv];
    inliers += s[kInliers];
    block_scores[b] = Eigen::Vector3d(s[kS0], s[kS1], s[kS2]);
    block_counts[b] = static_cast<int>(std::lround(s[kUsed]));
    lin.g += block_scores[b];
  }
  FinishLinearization(c, inliers, block_scores, block_counts, &lin);
  return lin;
}

}  // namespace fleetloc::tracking
