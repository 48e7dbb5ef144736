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
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "tracking/dense_linearization.h"
#include "tracking/direct_aligner.h"
#include "tracking/direct_aligner_parts.h"
#include "tracking/frame_mosaic_warp.h"

namespace fleetloc::tracking {

using geometry::Difference;
using geometry::Pose2;
using geometry::PoseWithCovariance;
using direct_detail::ApplyStep;
using direct_detail::Median;
using direct_detail::PixelPoint;
using direct_detail::RotationBlock;

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

}  // namespace

// The pyramid, normalized like the mosaic, and at each level the strongest-gradient pixel of
// every cell (cells sized so that at most max_points are kept), away from the clipped border.
std::vector<DirectAligner::Level> DirectAligner::BuildLevels(const cv::Mat& frame, int finest,
                                                             int coarsest) const {
  std::vector<Level> levels(coarsest + 1);
  cv::Mat image = frame;
  for (int l = 0; l <= coarsest; ++l) {
    if (l > 0) cv::resize(image, image, {image.cols / 2, image.rows / 2}, 0, 0, cv::INTER_AREA);
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
    const cv::Mat& t = level.normalized;
    const int b = level.border, w = t.cols - 2 * b, h = t.rows - 2 * b;
    if (w <= 0 || h <= 0) continue;
    const int cell =
        std::max(1, static_cast<int>(std::ceil(std::sqrt(double(w) * h / options_.max_points))));
    for (int cy = b; cy < b + h; cy += cell) {
      for (int cx = b; cx < b + w; cx += cell) {
        float best = 1e-4f;
        PixelPoint point;
        for (int y = cy; y < std::min(cy + cell, b + h); ++y) {
          const float* row = t.ptr<float>(y);
          const uchar* masked = occluded.ptr<uchar>(y);
          for (int x = cx; x < std::min(cx + cell, b + w); ++x) {
            if (masked[x]) continue;
            const float gx = 0.5f * (row[x + 1] - row[x - 1]);
            const float gy = 0.5f * (t.ptr<float>(y + 1)[x] - t.ptr<float>(y - 1)[x]);
            const float g2 = gx * gx + gy * gy;
            if (g2 <= best) continue;
            best = g2;
            point.u = x + 0.5f, point.v = y + 0.5f, point.value = row[x];
            point.du0 = static_cast<float>((x + 0.5) * (1 << l) - camera_.cx_px);
            point.dv0 = static_cast<float>((y + 0.5) * (1 << l) - camera_.cy_px);
          }
        }
        if (best > 1e-4f) level.points.push_back(point);
      }
    }
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
    min_x = std::min(min_x, m.x()), max_x = std::max(max_x, m.x());
    min_y = std::min(min_y, m.y()), max_y = std::max(max_y, m.y());
  }
  constexpr int kMargin = 8;
  MosaicBlock source;
  source.rect = cv::Rect(static_cast<int>(std::floor(min_x)) - kMargin,
                         static_cast<int>(std::floor(min_y)) - kMargin,
                         static_cast<int>(std::ceil(max_x - min_x)) + 2 * kMargin + 1,
                         static_cast<int>(std::ceil(max_y - min_y)) + 2 * kMargin + 1);
  source.level_size = {std::max(1, (layout.width_px + (1 << l) - 1) >> l),
                       std::max(1, (layout.height_px + (1 << l) - 1) >> l)};
  const cv::Mat block = mosaic_->ReadBlock(l, source.rect);
  cv::Mat grad_x, grad_y;
  cv::Sobel(block, grad_x, CV_32F, 1, 0, 1, 0.5);
  cv::Sobel(block, grad_y, CV_32F, 0, 1, 1, 0.5);
  cv::merge(std::vector<cv::Mat>{block, grad_x, grad_y, cv::Mat::zeros(block.size(), CV_32F)},
            source.texels);
  return std::make_unique<MosaicBlock>(std::move(source));
}

// The mosaic view at each of the level's points when the camera is at `pose`, and the Jacobian
// of the residual with respect to the warp increment (before the contrast gain).
DirectAligner::LevelSamples DirectAligner::SampleLevel(const Level& level,
                                                       const MosaicBlock& source,
                                                       const Pose2& pose) const {
  const FrameMosaicWarp warp =
      FrameMosaicWarp::For(pose, camera_, mosaic_->layout().geo).AtLevel(level.level);
  // The Jacobian takes the gradient of the warped mosaic (clean, noise-free) in frame axes rather
  // than the frame's own: the noisy frame gradient overstates the curvature and makes the
  // inverse-compositional steps too short (measured: linear convergence at ratio 0.75 on a plain
  // floor; with the mosaic's gradient, 2–4 iterations per level).
  const Eigen::Matrix2f to_frame = warp.linear.transpose().cast<float>();
  const Eigen::Matrix2f linear = warp.linear.cast<float>();
  const Eigen::Vector2f offset = warp.offset.cast<float>();
  const float scale = 1.0f / (1 << level.level);
  const size_t n = level.points.size();
  LevelSamples s;
  s.jacobians.resize(n), s.valid.resize(n), s.values.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const PixelPoint& p = level.points[i];
    const Eigen::Vector2f m = linear * Eigen::Vector2f(p.u, p.v) + offset;
    float sample[3] = {0.0f, 0.0f, 0.0f};
    s.valid[i] = source.Sample(m.x(), m.y(), sample);
    if (!s.valid[i]) continue;
    s.values[i] = sample[0];
    s.stv += p.value * sample[0], s.svv += sample[0] * sample[0];
    const Eigen::Vector2f g = to_frame * Eigen::Vector2f(sample[1], sample[2]);
    s.jacobians[i] =
        Eigen::Vector3f(-g.y() * scale, -g.x() * scale, (g.x() * p.dv0 - g.y() * p.du0) * scale);
  }
  return s;
}

// Residuals, robust weights and the weighted normal equations of `level` at `pose` (sigma ≤ 0:
// estimated from the residuals' MAD), with the fit's quality and the per-block scores the
// sandwich covariance needs.
Linearization DirectAligner::Linearize(const Level& level, const MosaicBlock& source,
                                       const Pose2& pose, double sigma, double gain) const {
  LevelSamples s = SampleLevel(level, source, pose);
  Linearization lin;
  lin.gain = gain > 0 ? gain : LeastSquaresGain(s.stv, s.svv);
  const size_t n = level.points.size();
  std::vector<float> residuals(n), magnitudes;
  magnitudes.reserve(n);
  for (size_t i = 0; i < n; ++i) {
    if (!s.valid[i]) continue;
    residuals[i] = level.points[i].value - static_cast<float>(lin.gain) * s.values[i];
    s.jacobians[i] *= static_cast<float>(lin.gain);
    magnitudes.push_back(std::abs(residuals[i]));
  }
  lin.points = static_cast<int>(magnitudes.size());
  if (lin.points < 3) return lin;
  lin.sigma = sigma > 0 ? sigma : std::max(1e-3, 1.4826 * Median(magnitudes));
  AccumulateWeighted(level, s, residuals, options_.tukey_c * lin.sigma, &lin);
  return lin;
}

// The Tukey-weighted normal equations, correlation sums and per-block scores of the residuals.
void DirectAligner::AccumulateWeighted(const Level& level, const LevelSamples& s,
                                       const std::vector<float>& residuals, double cutoff,
                                       Linearization* lin) const {
  std::vector<Eigen::Vector3d> block_scores(kScoreBlocks * kScoreBlocks, Eigen::Vector3d::Zero());
  std::vector<int> block_counts(kScoreBlocks * kScoreBlocks, 0);
  CorrelationSums c;
  int inliers = 0;
  for (size_t i = 0; i < residuals.size(); ++i) {
    if (!s.valid[i]) continue;
    const double w = TukeyWeight(residuals[i], cutoff);
    const PixelPoint& p = level.points[i];
    const double t = p.value, v = s.values[i];
    c.sw += w, c.st += w * t, c.sv += w * v, c.stt += w * t * t, c.svv += w * v * v;
    c.stv += w * t * v;
    if (w > 0.5) ++inliers;
    if (w <= 0.0) continue;
    const Eigen::Vector3d j = s.jacobians[i].cast<double>();
    lin->h.noalias() += w * j * j.transpose();
    lin->g.noalias() += (w * residuals[i]) * j;
    const int bx =
        std::min(kScoreBlocks - 1, static_cast<int>(p.u * kScoreBlocks / level.normalized.cols));
    const int by =
        std::min(kScoreBlocks - 1, static_cast<int>(p.v * kScoreBlocks / level.normalized.rows));
    block_scores[by * kScoreBlocks + bx] += (w * residuals[i]) * j;
    ++block_counts[by * kScoreBlocks + bx];
  }
  lin->inlier_fraction = double(inliers) / lin->points;
  lin->correlation = c.Correlation();
  lin->next_gain = c.Gain();
  lin->score_spread = ScoreSpread(block_scores, block_counts, lin->g);
}

// Robust MAP Gauss–Newton at one level from `pose`: the level's final pose, its linearization
// there in `final_fit`.
Pose2 DirectAligner::AlignLevel(const Level& level, const PoseWithCovariance& prior, Pose2 pose,
                                double tolerance_px, int* iterations, Linearization* final_fit,
                                bool fit_gain) const {
  const Source source = ReadSource(level, pose);
  return GaussNewton(
      [&](const Pose2& at, double sigma, double gain) {
        return Linearize(level, *source, at, sigma, gain);
      },
      level.level, options_.max_iterations, prior, pose, tolerance_px, iterations, final_fit,
      fit_gain);
}

// Up to `max_iterations` maximum a posteriori steps from `pose`, each from `linearize` at the
// current pose (the residual scale estimated at the first, then kept); stops once a step moves no
// pixel of the level more than `tolerance_px`. The final linearization in `final_fit`.
Pose2 DirectAligner::GaussNewton(const LinearizeAt& linearize, int level, int max_iterations,
                                 const PoseWithCovariance& prior, Pose2 pose, double tolerance_px,
                                 int* iterations, Linearization* final_fit, bool fit_gain) const {
  const double res = camera_.resolution_m;
  const Eigen::Matrix3d prior_information = prior.covariance.inverse();
  const Eigen::Matrix3d to_px = Eigen::Vector3d(res, res, 1.0).asDiagonal();
  const double frame_radius_px = 0.5 * std::hypot(camera_.width_px, camera_.height_px);
  double sigma = 0.0;  // estimated at the first iteration, then kept
  // The frame's contrast against the view: estimated at the first iteration, then re-fitted with
  // each iteration's robust weights (see kMinGain in dense_linearization.h); 1 when not fitted.
  double gain = fit_gain ? 0.0 : 1.0;
  for (int it = 0; it < max_iterations; ++it) {
    ++*iterations;
    const Linearization lin = linearize(pose, sigma, gain);
    if (lin.points < 3) break;
    sigma = lin.sigma;
    if (fit_gain) gain = lin.next_gain;
    // Maximum a posteriori step: image term (its information scaled by the residual variance and
    // the correlation factor) and the prior, whose map delta is ≈ −B·S·q.
    const double inv_var = 1.0 / (sigma * sigma * options_.correlation_factor);
    const Eigen::Matrix3d bs = RotationBlock(pose) * to_px;
    const Eigen::Matrix3d hp = bs.transpose() * prior_information * bs;
    const Eigen::Vector3d gp = bs.transpose() * prior_information * Difference(pose, prior.pose);
    const Eigen::Vector3d q = (lin.h * inv_var + hp).ldlt().solve(-lin.g * inv_var + gp);
    if (!q.allFinite()) break;
    pose = ApplyStep(pose, q, res);
    const double moved_px = (q.head<2>().norm() + std::abs(q.z()) * frame_radius_px) / (1 << level);
    if (moved_px < tolerance_px) break;
  }
  *final_fit = linearize(pose, sigma, gain);
  return pose;
}

}  // namespace fleetloc::tracking
