// Robust normal equations over a whole frame (see dense_linearization.h).
#include "tracking/dense_linearization.h"

#include <algorithm>
#include <cmath>

namespace fleetloc::tracking {

double CorrelationSums::Correlation() const {
  const double w = std::max(sw, 1e-12);
  const double var_t = stt - st * st / w, var_v = svv - sv * sv / w;
  return var_t > 0 && var_v > 0 ? (stv - st * sv / w) / std::sqrt(var_t * var_v) : 0.0;
}

double LeastSquaresGain(double stv, double svv) {
  if (!(svv > 1e-9)) return 1.0;
  return std::clamp(stv / svv, kMinGain, kMaxGain);
}

double CorrelationSums::Gain() const { return LeastSquaresGain(stv, svv); }

void FinishLinearization(const CorrelationSums& c, double inliers,
                         const std::vector<Eigen::Vector3d>& block_scores,
                         const std::vector<int>& block_counts, Linearization* lin) {
  lin->h(1, 0) = lin->h(0, 1);
  lin->h(2, 0) = lin->h(0, 2);
  lin->h(2, 1) = lin->h(1, 2);
  lin->correlation = c.Correlation();
  lin->next_gain = c.Gain();
  lin->inlier_fraction = inliers / lin->points;
  lin->score_spread = ScoreSpread(block_scores, block_counts, lin->g);
}

void InLevel0Pixels(int level, Linearization* lin) {
  if (level == 0) return;
  const Eigen::DiagonalMatrix<double, 3> s(1.0 / (1 << level), 1.0 / (1 << level), 1.0);
  lin->h = s * lin->h * s;
  lin->g = s * lin->g;
  lin->score_spread = s * lin->score_spread * s;
  lin->robust_curvature /= double(1 << level) * (1 << level);
}

Eigen::Matrix3d SandwichPlusIndependent(const Linearization& fit, const Eigen::Matrix3d& h_inv) {
  return h_inv * fit.score_spread * h_inv + fit.sigma * fit.sigma * h_inv;
}

Eigen::Matrix3d ImageCovariance(const Linearization& fit, const Eigen::Matrix3d& h_inv) {
  if (!fit.robust_curvature_summed) return SandwichPlusIndependent(fit, h_inv);
  const Eigen::Matrix3d sandwich = h_inv * fit.score_spread * h_inv;
  double share =
      std::clamp(fit.robust_curvature / (fit.h(0, 0) + fit.h(1, 1)), kMinCurvatureShare, 1.0);
  if (fit.secant_curvature > 0) share = std::clamp(fit.secant_curvature, share, 2 * share);
  return sandwich / (share * share);
}

double SecantCurvature(const Linearization& first, const Linearization& last,
                       const Eigen::Vector3d& step) {
  const Eigen::Vector2d s = step.head<2>();
  const double predicted = s.dot(first.h.topLeftCorner<2, 2>() * s);
  if (s.norm() < kMinSecantStepPx || !(predicted > 0)) return 0.0;
  return (last.g - first.g).head<2>().dot(s) / predicted;
}

Eigen::Matrix3d ScoreSpread(const std::vector<Eigen::Vector3d>& block_scores,
                            const std::vector<int>& block_counts, const Eigen::Vector3d& total) {
  int pixels = 0, used_blocks = 0;
  for (int c : block_counts) {
    pixels += c;
    used_blocks += c > 0;
  }
  Eigen::Matrix3d spread = Eigen::Matrix3d::Zero();
  for (size_t b = 0; b < block_scores.size(); ++b) {
    if (block_counts[b] == 0) continue;
    const Eigen::Vector3d d = block_scores[b] - total * (double(block_counts[b]) / pixels);
    spread.noalias() += d * d.transpose();
  }
  if (used_blocks > 1) spread *= double(used_blocks) / (used_blocks - 1);
  return spread;
}

namespace {

// Every third pixel of every third row of the spans, with its precision (1 without a map): the
// scale and a starting gain need a few thousand samples, not all of them.
template <typename Visit>
void VisitSparseGrid(const cv::Mat& frame, const cv::Mat& view, const cv::Rect& inner,
                     const std::vector<cv::Range>& spans, const cv::Mat& precision, Visit visit) {
  for (int y = 0; y < inner.height; y += 3) {
    const float* t = frame.ptr<float>(inner.y + y) + inner.x;
    const float* v = view.ptr<float>(y + 1) + 1;
    const float* p = precision.empty() ? nullptr : precision.ptr<float>(inner.y + y) + inner.x;
    for (int x = spans[y].start; x < spans[y].end; x += 3) visit(t[x], v[x], p ? p[x] : 1.0f);
  }
}

double SparseGain(const cv::Mat& frame, const cv::Mat& view, const cv::Rect& inner,
                  const std::vector<cv::Range>& spans, const cv::Mat& precision) {
  double stv = 0, svv = 0;
  VisitSparseGrid(frame, view, inner, spans, precision, [&](float t, float v, float p) {
    stv += p * t * v;
    svv += p * v * v;
  });
  return LeastSquaresGain(stv, svv);
}

// 1.4826 × the median absolute residual t − gain·v, each times √precision, over the sparse grid.
double RobustScale(const cv::Mat& frame, const cv::Mat& view, const cv::Rect& inner,
                   const std::vector<cv::Range>& spans, const cv::Mat& precision, float gain) {
  // Filled by index into a buffer sized for the whole grid (push_back's capacity check per sample
  // cost as much as the sample).
  std::vector<float> magnitudes((inner.width / 3 + 1) * (inner.height / 3 + 1));
  size_t count = 0;
  VisitSparseGrid(frame, view, inner, spans, precision, [&](float t, float v, float p) {
    magnitudes[count++] = std::sqrt(p) * std::abs(t - gain * v);
  });
  if (count == 0) return 1e-3;
  magnitudes.resize(count);
  const auto mid = magnitudes.begin() + magnitudes.size() / 2;
  std::nth_element(magnitudes.begin(), mid, magnitudes.end());
  return std::max(1e-3, 1.4826 * *mid);
}

// Sums over one row's span, in floats (a span is at most a frame row, so float sums keep ~6
// digits). The per-pixel scores w·r·J go to `score0..2` for the block sums of the sandwich
// covariance.
struct RowSums {
  float h00 = 0, h01 = 0, h02 = 0, h11 = 0, h12 = 0, h22 = 0;
  float sw = 0, st = 0, sv = 0, stt = 0, svv = 0, stv = 0;
  float inliers = 0, robust_curvature = 0;
};

// clang-format off
enum RowSum {
  kH00, kH01, kH02, kH11, kH12, kH22,  // the normal equations
  kSw, kSt, kSv, kStt, kSvv, kStv,     // the correlation sums
  kIn, kPsi, kSums                     // inliers, Σ p·ψ′·(j0² + j1²); the count
};
// clang-format on

// One pixel's terms added to lane sums `acc[sum]`. `p`: the pixels' precisions. The Tukey weight
// is of the residual in units of its own spread (√p·r); the normal equations take p times it.
// The correlation sums keep the Tukey weight alone: the gates on the correlation were set on it.
inline void AddPixel(const float* t, const float* p, const float* up, const float* mid,
                     const float* down, int x, float du, float dv, float gain, float inv_cutoff_sq,
                     float* score0, float* score1, float* score2, float* acc, int stride) {
  const float gx = 0.5f * gain * (mid[x + 1] - mid[x - 1]);
  const float gy = 0.5f * gain * (down[x] - up[x]);
  const float v = mid[x];
  const float r = t[x] - gain * v;
  const float a = p[x] * r * r * inv_cutoff_sq;
  // Branch-free so the lanes vectorize: max(0, 1 − a)², and 1 when w > 0.5 (a < 1 − √½).
  const float b = 0.5f * ((1.0f - a) + std::abs(1.0f - a));
  const float w = b * b;
  const float inlier = 0.5f + 0.5f * std::copysign(1.0f, 0.29289322f - a);
  // J for q = (qx, qy, qθ) in camera_ground axes: frame x is ground −y, frame y is ground −x.
  const float j0 = -gy, j1 = -gx, j2 = gx * dv - gy * du;
  const float wp = w * p[x];
  const float wj0 = wp * j0, wj1 = wp * j1, wj2 = wp * j2;
  acc[kH00 * stride] += wj0 * j0;
  acc[kH01 * stride] += wj0 * j1;
  acc[kH02 * stride] += wj0 * j2;
  acc[kH11 * stride] += wj1 * j1;
  acc[kH12 * stride] += wj1 * j2;
  acc[kH22 * stride] += wj2 * j2;
  score0[x] = wj0 * r;
  score1[x] = wj1 * r;
  score2[x] = wj2 * r;
  acc[kSw * stride] += w;
  acc[kSt * stride] += w * t[x];
  acc[kSv * stride] += w * v;
  acc[kStt * stride] += w * t[x] * t[x];
  acc[kSvv * stride] += w * v * v;
  acc[kStv * stride] += w * t[x] * v;
  acc[kIn * stride] += inlier;
  // ψ′ = (1 − a)(1 − 5a) under the cut-off (negative past a = 1/5), 0 beyond it, as b is.
  acc[kPsi * stride] += b * (1.0f - 5.0f * a) * p[x] * (j0 * j0 + j1 * j1);
}

// `t`, `p`: the frame row and its precisions from the span's first pixel; `up`, `mid`, `down`: the
// view rows above, at and below it, also from the span's first pixel (one pixel of view lies on
// either side of it). `du0`: the first pixel's column offset from the principal point; `dv`: the
// row's. Eight lanes of independent sums, so the compiler vectorizes the lanes (a plain reduction
// it may not reorder); built for AVX2 as well as the baseline, the loader picks the best the CPU
// has.
__attribute__((target_clones("avx2", "default"))) RowSums SumRow(
    const float* __restrict t, const float* __restrict p, const float* __restrict up,
    const float* __restrict mid, const float* __restrict down, int n, float du0, float dv,
    float gain, float inv_cutoff_sq, float* __restrict score0, float* __restrict score1,
    float* __restrict score2) {
  constexpr int kLanes = 8;
  alignas(32) float lanes[kSums][kLanes] = {};
  int x = 0;
  for (; x + kLanes <= n; x += kLanes) {
    for (int k = 0; k < kLanes; ++k) {
      AddPixel(t, p, up, mid, down, x + k, du0 + x + k, dv, gain, inv_cutoff_sq, score0, score1,
               score2, &lanes[0][k], kLanes);
    }
  }
  float tail[kSums] = {};
  for (; x < n; ++x) {
    AddPixel(t, p, up, mid, down, x, du0 + x, dv, gain, inv_cutoff_sq, score0, score1, score2, tail,
             1);
  }
  float sums[kSums];
  for (int s = 0; s < kSums; ++s) {
    sums[s] = tail[s];
    for (int k = 0; k < kLanes; ++k) sums[s] += lanes[s][k];
  }
  return {sums[kH00], sums[kH01], sums[kH02], sums[kH11], sums[kH12], sums[kH22], sums[kSw],
          sums[kSt],  sums[kSv],  sums[kStt], sums[kSvv], sums[kStv], sums[kIn],  sums[kPsi]};
}

// Σ of each of the three score rows over [0, n), in one pass (built for AVX2 as well, as SumRow).
__attribute__((target_clones("avx2", "default"))) Eigen::Vector3d SumScores(
    const float* __restrict s0, const float* __restrict s1, const float* __restrict s2, int n) {
  float a = 0, b = 0, c = 0;
#pragma omp simd reduction(+ : a, b, c)
  for (int i = 0; i < n; ++i) {
    a += s0[i];
    b += s1[i];
    c += s2[i];
  }
  return {a, b, c};
}

// One row's sums added to the frame's normal equations and correlation sums.
void AddRowSums(const RowSums& s, Linearization* lin, CorrelationSums* c, double* inliers) {
  lin->h(0, 0) += s.h00;
  lin->h(0, 1) += s.h01;
  lin->h(0, 2) += s.h02;
  lin->h(1, 1) += s.h11;
  lin->h(1, 2) += s.h12;
  lin->h(2, 2) += s.h22;
  c->sw += s.sw;
  c->st += s.st;
  c->sv += s.sv;
  c->stt += s.stt;
  c->svv += s.svv;
  c->stv += s.stv;
  *inliers += s.inliers;
  lin->robust_curvature += s.robust_curvature;
}

}  // namespace

Linearization LinearizeWholeFrame(const cv::Mat& frame, const cv::Mat& view, const cv::Rect& inner,
                                  const std::vector<cv::Range>& spans_in,
                                  const Eigen::Vector2d& principal_px, double tukey_c, double sigma,
                                  double gain, const cv::Mat& precision) {
  CV_Assert(frame.type() == CV_32F && view.type() == CV_32F);
  CV_Assert(view.cols == inner.width + 2 && view.rows == inner.height + 2);
  CV_Assert((cv::Rect(0, 0, frame.cols, frame.rows) & inner) == inner);
  CV_Assert(spans_in.empty() || spans_in.size() == static_cast<size_t>(inner.height));
  CV_Assert(precision.empty() || (precision.type() == CV_32F && precision.size() == frame.size()));
  Linearization lin;
  if (inner.width < kScoreBlocks || inner.height < kScoreBlocks) return lin;
  std::vector<cv::Range> spans = spans_in;
  if (spans.empty()) spans.assign(inner.height, cv::Range(0, inner.width));
  for (cv::Range& span : spans) {
    span.start = std::max(span.start, 0);
    span.end = std::min(span.end, inner.width);
    if (span.end > span.start) lin.points += span.end - span.start;
  }
  if (lin.points < 3) return lin;
  lin.robust_curvature_summed = true;
  lin.gain = gain > 0 ? gain : SparseGain(frame, view, inner, spans, precision);
  lin.sigma = sigma > 0 ? sigma : RobustScale(frame, view, inner, spans, precision, lin.gain);
  const std::vector<float> uniform(precision.empty() ? inner.width : 0, 1.0f);
  const float inv_cutoff_sq = static_cast<float>(1.0 / (tukey_c * tukey_c * lin.sigma * lin.sigma));
  std::vector<Eigen::Vector3d> block_scores(kScoreBlocks * kScoreBlocks, Eigen::Vector3d::Zero());
  std::vector<int> block_counts(kScoreBlocks * kScoreBlocks, 0);
  CorrelationSums c;
  double inliers = 0;
  std::vector<float> scores(3 * inner.width);
  float* score[3] = {scores.data(), scores.data() + inner.width, scores.data() + 2 * inner.width};
  for (int y = 0; y < inner.height; ++y) {
    const int x0 = spans[y].start, n = spans[y].end - spans[y].start;
    if (n <= 0) continue;
    const float* t = frame.ptr<float>(inner.y + y) + inner.x + x0;
    const float* p =
        precision.empty() ? uniform.data() + x0 : precision.ptr<float>(inner.y + y) + inner.x + x0;
    const float* up = view.ptr<float>(y) + 1 + x0;
    const float* mid = view.ptr<float>(y + 1) + 1 + x0;
    const float* down = view.ptr<float>(y + 2) + 1 + x0;
    const float dv = static_cast<float>(inner.y + y + 0.5 - principal_px.y());
    const float du0 = static_cast<float>(inner.x + x0 + 0.5 - principal_px.x());
    const RowSums s = SumRow(t, p, up, mid, down, n, du0, dv, lin.gain, inv_cutoff_sq,
                             score[0] + x0, score[1] + x0, score[2] + x0);
    AddRowSums(s, &lin, &c, &inliers);
    const int by = y * kScoreBlocks / inner.height;
    for (int bx = 0; bx < kScoreBlocks; ++bx) {
      const int b0 = std::max(bx * inner.width / kScoreBlocks, spans[y].start);
      const int b1 = std::min((bx + 1) * inner.width / kScoreBlocks, spans[y].end);
      if (b1 <= b0) continue;
      const Eigen::Vector3d block_score =
          SumScores(score[0] + b0, score[1] + b0, score[2] + b0, b1 - b0);
      lin.g += block_score;
      block_scores[by * kScoreBlocks + bx] += block_score;
      block_counts[by * kScoreBlocks + bx] += b1 - b0;
    }
  }
  FinishLinearization(c, inliers, block_scores, block_counts, &lin);
  return lin;
}

}  // namespace fleetloc::tracking
