// The dense aligner's frame pyramid and its robust Gauss–Newton over one level (see
// direct_aligner.h).
//
// Parametrization: the warp increment q = (qx, qy, qθ) acts on camera_ground points, g ↦ q ⊕ g,
// and is carried in level-0 pixels and radians. With frame pixel u ↔ ground g (docs/formats.md),
// the inverse-compositional step (Baker & Matthews 2004) minimizes Σ ρ(T(W(u; q)) − I(A(u))) where
// T is the normalized frame, I the normalized mosaic and A the current frame → mosaic warp; the
// Jacobian of T(W(u; q)) at q = 0 is fixed per pixel, and the update is pose ← pose ⊕ q⁻¹.
#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>
#include <opencv2/core/hal/intrin.hpp>
#include <opencv2/imgproc.hpp>

#include "tracking/dense_linearization.h"
#include "tracking/direct_aligner.h"
#include "tracking/direct_aligner_parts.h"
#include "tracking/frame_mosaic_warp.h"
#include "tracking/frame_pyramid.h"

namespace fleetloc::tracking {

using direct_detail::ApplyStep;
using direct_detail::Median;
using direct_detail::RotationBlock;
using geometry::Difference;
using geometry::Pose2;
using geometry::PoseWithCovariance;

namespace {

// Pixels near something the mosaic cannot have: where the frame's local contrast is far above
// the floor's typical one (debris, tyre marks, dust edges, shadow edges). Local normalization
// would squash such an occluder to the floor's range, where no robust weight could tell it from
// texture, so it is masked before it is normalized. `ratio` is relative to the frame's median
// local standard deviation, so the rule holds on plain and rich floors alike. `variance` is the
// frame's over the normalization window (the normalization computes it). Returns CV_8U, non-zero
// where pixels must not be used.
cv::Mat OccluderMask(const cv::Mat& variance, int window, double ratio) {
  std::vector<float> samples;
  for (int y = 0; y < variance.rows; y += 4) {
    for (int x = 0; x < variance.cols; x += 4) samples.push_back(variance.at<float>(y, x));
  }
  const double median_variance = std::max(1e-3, Median(samples));
  cv::Mat mask = variance > ratio * ratio * median_variance;
  cv::dilate(mask, mask, cv::getStructuringElement(cv::MORPH_RECT, {window, window}));
  return mask;
}

// One chosen frame pixel: its level coordinates, normalized value, level-0 offset from the
// principal point (for the rotation column of the Jacobian) and score block.
struct PixelPoint {
  float u = 0, v = 0;
  float value = 0;
  float du0 = 0, dv0 = 0;
  int block = 0;
};

// The score block (kScoreBlocks² over the level, row-major) holding `point`.
int ScoreBlock(const PixelPoint& point, const cv::Size& level_size) {
  const int bx =
      std::min(kScoreBlocks - 1, static_cast<int>(point.u * kScoreBlocks / level_size.width));
  const int by =
      std::min(kScoreBlocks - 1, static_cast<int>(point.v * kScoreBlocks / level_size.height));
  return by * kScoreBlocks + bx;
}

// `chosen` as arrays grouped by score block, each block's pixels in the order chosen.
PointSet Grouped(const std::vector<PixelPoint>& chosen) {
  PointSet set;
  for (const PixelPoint& p : chosen) ++set.block_start[p.block + 1];
  for (int b = 0; b < kScoreBlocks * kScoreBlocks; ++b) {
    set.block_start[b + 1] += set.block_start[b];
  }
  const size_t n = chosen.size();
  set.u.resize(n);
  set.v.resize(n);
  set.value.resize(n);
  set.du0.resize(n);
  set.dv0.resize(n);
  std::array<int, kScoreBlocks * kScoreBlocks> next{};
  std::copy(set.block_start.begin(), set.block_start.end() - 1, next.begin());
  for (const PixelPoint& p : chosen) {
    const int i = next[p.block]++;
    set.u[i] = p.u;
    set.v[i] = p.v;
    set.value[i] = p.value;
    set.du0[i] = p.du0;
    set.dv0[i] = p.dv0;
  }
  return set;
}

// One texel of WithGradients: the value at `x` of `row` with the neighbours `left`/`right` in
// the row and the pixels `up`/`down` above and below it.
inline void StoreTexel(float value, float left, float right, float up, float down, float* out) {
  out[0] = value;
  out[1] = 0.5f * (right - left);
  out[2] = 0.5f * (down - up);
  out[3] = 0.0f;
}

// `block` (CV_32F) with its gradients, interleaved as the bilinear sampler reads them: value,
// d/dx, d/dy (half the neighbours' difference, 0 on the block's edge as OpenCV's reflected border
// gives), 0. One vectorized pass where two Sobel filters and a merge took three, and the same
// floats: the halving is exact.
cv::Mat WithGradients(const cv::Mat& block) {
  cv::Mat texels(block.size(), CV_32FC4);
  const int last_x = block.cols - 1, last_y = block.rows - 1;
  for (int y = 0; y <= last_y; ++y) {
    const float* row = block.ptr<float>(y);
    const float* up = block.ptr<float>(y > 0 ? y - 1 : std::min(1, last_y));
    const float* down = block.ptr<float>(y < last_y ? y + 1 : std::max(0, last_y - 1));
    float* out = texels.ptr<float>(y);
    if (last_x < 2) {  // too narrow for an inside
      for (int x = 0; x <= last_x; ++x) StoreTexel(row[x], 0, 0, up[x], down[x], out + 4 * x);
      continue;
    }
    StoreTexel(row[0], row[1], row[1], up[0], down[0], out);
    int x = 1;
#if CV_SIMD128
    const cv::v_float32x4 half = cv::v_setall_f32(0.5f), zero = cv::v_setzero_f32();
    for (; x + 4 <= last_x; x += 4) {
      const cv::v_float32x4 gx = half * (cv::v_load(row + x + 1) - cv::v_load(row + x - 1));
      const cv::v_float32x4 gy = half * (cv::v_load(down + x) - cv::v_load(up + x));
      cv::v_store_interleave(out + 4 * x, cv::v_load(row + x), gx, gy, zero);
    }
#endif
    for (; x < last_x; ++x) StoreTexel(row[x], row[x - 1], row[x + 1], up[x], down[x], out + 4 * x);
    StoreTexel(row[last_x], row[last_x - 1], row[last_x - 1], up[last_x], down[last_x],
               out + 4 * last_x);
  }
  return texels;
}

// Folds row y of `t`'s squared central-difference gradient over columns [x0, x1) into the
// column maxima of a band of rows: where it exceeds `column_best` (0 where `occluded`), the value
// and y replace them, so each column keeps its first row among equals. Four columns at a time
// (the same floats: products and sums, no fused multiply-add).
void FoldGradientRow(const cv::Mat& t, const cv::Mat& occluded, int y, int x0, int x1,
                     float* column_best, int* column_best_y) {
  const float* row = t.ptr<float>(y);
  const float* up = t.ptr<float>(y - 1);
  const float* down = t.ptr<float>(y + 1);
  const uchar* masked = occluded.ptr<uchar>(y);
  int x = x0;
#if CV_SIMD128
  const cv::v_float32x4 half = cv::v_setall_f32(0.5f), zero = cv::v_setzero_f32();
  const cv::v_int32x4 y_v = cv::v_setall_s32(y);
  for (; x + 4 <= x1; x += 4) {
    const cv::v_float32x4 gx = half * (cv::v_load(row + x + 1) - cv::v_load(row + x - 1));
    const cv::v_float32x4 gy = half * (cv::v_load(down + x) - cv::v_load(up + x));
    const cv::v_float32x4 open =
        cv::v_reinterpret_as_f32(cv::v_load_expand_q(masked + x) == cv::v_setzero_u32());
    const cv::v_float32x4 g2 = cv::v_select(open, gx * gx + gy * gy, zero);
    const cv::v_float32x4 best = cv::v_load(column_best + x);
    const cv::v_float32x4 better = g2 > best;
    cv::v_store(column_best + x, cv::v_select(better, g2, best));
    cv::v_store(column_best_y + x,
                cv::v_select(cv::v_reinterpret_as_s32(better), y_v, cv::v_load(column_best_y + x)));
  }
#endif
  for (; x < x1; ++x) {
    const float gx = 0.5f * (row[x + 1] - row[x - 1]);
    const float gy = 0.5f * (down[x] - up[x]);
    const float g2 = masked[x] ? 0.0f : gx * gx + gy * gy;
    const bool better = g2 > column_best[x];
    column_best[x] = better ? g2 : column_best[x];
    column_best_y[x] = better ? y : column_best_y[x];
  }
}

// At a level whose normalized frame is `t`, the strongest-gradient unoccluded pixel of every
// cell (cells sized so that at most `max_points` are kept; the first in row order among equals),
// away from the clipped `border`, grouped by score block. `principal`: the principal point in
// level-0 px. Each band of cell rows is reduced down its columns first (FoldGradientRow), then
// along each cell's columns, the earlier row winning a tie: the pixel a scan in row order picks,
// without its per-pixel branches (measured at 640×480: the scan was a quarter of the frame's
// instructions on painted pavement under `all`).
PointSet ChoosePoints(const cv::Mat& t, const cv::Mat& occluded, int border, int level,
                      const cv::Point2d& principal, int max_points) {
  const int b = border, w = t.cols - 2 * b, h = t.rows - 2 * b;
  if (w <= 0 || h <= 0) return {};
  constexpr float kNone = 1e-4f;  // a cell's best must exceed this
  const int cell = std::max(1, static_cast<int>(std::ceil(std::sqrt(double(w) * h / max_points))));
  std::vector<float> column_best(t.cols);
  std::vector<int> column_best_y(t.cols);
  std::vector<PixelPoint> chosen;
  for (int cy = b; cy < b + h; cy += cell) {
    std::fill(column_best.begin(), column_best.end(), kNone);
    for (int y = cy; y < std::min(cy + cell, b + h); ++y) {
      FoldGradientRow(t, occluded, y, b, b + w, column_best.data(), column_best_y.data());
    }
    for (int cx = b; cx < b + w; cx += cell) {
      float best = kNone;
      int x = -1;
      for (int c = cx; c < std::min(cx + cell, b + w); ++c) {
        if (column_best[c] > best ||
            (column_best[c] == best && x >= 0 && column_best_y[c] < column_best_y[x])) {
          best = column_best[c];
          x = c;
        }
      }
      if (x < 0) continue;
      const int y = column_best_y[x];
      PixelPoint point;
      point.u = x + 0.5f;
      point.v = y + 0.5f;
      point.value = t.ptr<float>(y)[x];
      point.du0 = static_cast<float>((x + 0.5) * (1 << level) - principal.x);
      point.dv0 = static_cast<float>((y + 0.5) * (1 << level) - principal.y);
      point.block = ScoreBlock(point, t.size());
      chosen.push_back(point);
    }
  }
  return Grouped(chosen);
}

}  // namespace

// The pyramid, normalized like the mosaic, and each level's chosen pixels (ChoosePoints).
std::vector<DirectAligner::Level> DirectAligner::BuildLevels(const cv::Mat& frame, int finest,
                                                             int coarsest) const {
  std::vector<Level> levels(coarsest + 1);
  FramePyramid pyramid(frame);
  for (int l = 0; l <= coarsest; ++l) {
    const cv::Mat image = pyramid.Level(l);
    Level& level = levels[l];
    level.level = l;
    if (l < finest) continue;
    const int window = mosaic_->WindowAt(l);
    cv::Mat local_variance;
    level.normalized = mosaic_->Normalize(image, l, &local_variance);
    level.border = mosaic_->MarginAt(l);
    const cv::Mat occluded = OccluderMask(local_variance, window, options_.occluder_contrast_ratio);
    if (l == coarsest) {
      level.searched = level.normalized.clone();
      level.searched.setTo(0.0f, occluded);
    }
    level.points = ChoosePoints(level.normalized, occluded, level.border, l,
                                {camera_.cx_px, camera_.cy_px}, options_.max_points);
  }
  return levels;
}

// The normalized mosaic block under `level` at `pose`, with room for the level's iterations.
DirectAligner::Source DirectAligner::ReadSource(const Level& level, const Pose2& pose) const {
  const mosaic::MosaicLayout& layout = mosaic_->layout();
  const int l = level.level;
  const FrameMosaicWarp warp = FrameMosaicWarp::For(pose, camera_, layout.geo).AtLevel(l);
  double min_x = 1e300, min_y = 1e300, max_x = -1e300, max_y = -1e300;
  for (int c = 0; c < 4; ++c) {
    const Eigen::Vector2d m =
        warp(Eigen::Vector2d((c & 1) * level.normalized.cols, (c >> 1) * level.normalized.rows));
    min_x = std::min(min_x, m.x());
    max_x = std::max(max_x, m.x());
    min_y = std::min(min_y, m.y());
    max_y = std::max(max_y, m.y());
  }
  constexpr int kMargin = 8;
  MosaicBlock source;
  source.rect = cv::Rect(static_cast<int>(std::floor(min_x)) - kMargin,
                         static_cast<int>(std::floor(min_y)) - kMargin,
                         static_cast<int>(std::ceil(max_x - min_x)) + 2 * kMargin + 1,
                         static_cast<int>(std::ceil(max_y - min_y)) + 2 * kMargin + 1);
  source.level_size = {std::max(1, (layout.width_px + (1 << l) - 1) >> l),
                       std::max(1, (layout.height_px + (1 << l) - 1) >> l)};
  source.texels = WithGradients(mosaic_->ReadBlock(l, source.rect));
  return std::make_unique<MosaicBlock>(std::move(source));
}

// Residuals, robust weights and the weighted normal equations of `level` at `pose` (sigma ≤ 0:
// estimated from the residuals' MAD; gain ≤ 0: the least-squares contrast), with the fit's
// quality and the per-block scores the sandwich covariance needs.
Linearization DirectAligner::Linearize(const Level& level, const MosaicBlock& source,
                                       const Pose2& pose, double sigma, double gain,
                                       PointViews* views) const {
  const LevelWarp warp(
      FrameMosaicWarp::For(pose, camera_, mosaic_->layout().geo).AtLevel(level.level), level.level);
  warp.Views(source, level.points, views);
  return LinearizePoints(level.points, *views, options_.tukey_c, sigma, gain);
}

// Robust MAP Gauss–Newton at one level from `pose`: the level's final pose, its linearization
// there in `final_fit`.
Pose2 DirectAligner::AlignLevel(const Level& level, const PoseWithCovariance& prior, Pose2 pose,
                                double tolerance_px, int* iterations, Linearization* final_fit,
                                bool fit_gain) const {
  const Source source = ReadSource(level, pose);
  PointViews views;  // every iteration's, in one set of arrays
  return GaussNewton(
      [&](const Pose2& at, double sigma, double gain) {
        return Linearize(level, *source, at, sigma, gain, &views);
      },
      level.level, options_.max_iterations, prior, pose, tolerance_px, iterations, final_fit,
      fit_gain);
}

// Up to `max_iterations` maximum a posteriori steps from `pose`, each from `linearize` at the
// current pose (the residual scale estimated at the first, then kept); stops once a step moves no
// pixel of the level more than `tolerance_px`. The final linearization in `final_fit` (when
// not null). When the first step would move no pixel more than `final_at_start_px`, the start is
// already at the minimum: the linearization there is the final one and the pose is not moved (the
// caller's Combine takes that step), which saves a linearization.
Pose2 DirectAligner::GaussNewton(const LinearizeAt& linearize, int level, int max_iterations,
                                 const PoseWithCovariance& prior, Pose2 pose, double tolerance_px,
                                 int* iterations, Linearization* final_fit, bool fit_gain,
                                 double final_at_start_px) const {
  double sigma = 0.0;  // estimated at the first iteration, then kept
  // The frame's contrast against the view: estimated at the first iteration, then re-fitted with
  // each iteration's robust weights (see kMinGain in dense_linearization.h); 1 when not fitted.
  double gain = fit_gain ? 0.0 : 1.0;
  Linearization first;
  Eigen::Vector3d moved = Eigen::Vector3d::Zero();
  for (int it = 0; it < max_iterations; ++it) {
    ++*iterations;
    const Linearization lin = linearize(pose, sigma, gain);
    if (lin.points < 3) break;
    if (it == 0) first = lin;
    sigma = lin.sigma;
    if (fit_gain) gain = lin.next_gain;
    const Eigen::Vector3d q = MapStep(lin, pose, prior);
    if (!q.allFinite()) break;
    if (it == 0 && StepPx(q, level) <= final_at_start_px) {
      if (final_fit != nullptr) *final_fit = lin;
      return pose;
    }
    pose = ApplyStep(pose, q, camera_.resolution_m);
    moved += q;
    if (StepPx(q, level) < tolerance_px) break;
  }
  if (final_fit != nullptr) {
    *final_fit = linearize(pose, sigma, gain);
    // Above level 0 only: see ImageCovariance in tracking/dense_linearization.h.
    if (final_fit->robust_curvature_summed && level > 0) {
      final_fit->secant_curvature = SecantCurvature(first, *final_fit, moved);
    }
  }
  return pose;
}

// Image term (its information scaled by the residual variance and the correlation factor) and
// the prior, whose map delta is ≈ −B·S·q.
Eigen::Vector3d DirectAligner::MapStep(const Linearization& lin, const Pose2& pose,
                                       const PoseWithCovariance& prior) const {
  const double res = camera_.resolution_m;
  const Eigen::Matrix3d prior_information = prior.covariance.inverse();
  const Eigen::Matrix3d to_px = Eigen::Vector3d(res, res, 1.0).asDiagonal();
  const double inv_var = 1.0 / (lin.sigma * lin.sigma * options_.correlation_factor);
  const Eigen::Matrix3d bs = RotationBlock(pose) * to_px;
  const Eigen::Matrix3d hp = bs.transpose() * prior_information * bs;
  const Eigen::Vector3d gp = bs.transpose() * prior_information * Difference(pose, prior.pose);
  return (lin.h * inv_var + hp).ldlt().solve(-lin.g * inv_var + gp);
}

double DirectAligner::StepPx(const Eigen::Vector3d& q, int level) const {
  const double frame_radius_px = 0.5 * std::hypot(camera_.width_px, camera_.height_px);
  return (q.head<2>().norm() + std::abs(q.z()) * frame_radius_px) / (1 << level);
}

}  // namespace fleetloc::tracking
