// Robust coarse-to-fine inverse-compositional alignment of the whole frame (see direct_aligner.h).
//
// Parametrization: the warp increment q = (qx, qy, qθ) acts on camera_ground points, g ↦ q ⊕ g,
// and is carried in level-0 pixels and radians. With frame pixel u ↔ ground g (docs/formats.md),
// the inverse-compositional step (Baker & Matthews 2004) minimizes Σ ρ(T(W(u; q)) − I(A(u))) where
// T is the normalized frame, I the normalized mosaic and A the current frame → mosaic warp; the
// Jacobian of T(W(u; q)) at q = 0 is fixed per pixel, and the update is pose ← pose ⊕ q⁻¹.
#include "tracking/direct_aligner.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "geometry/convex_polygon.h"
#include "imaging/fast_patch.h"
#include "imaging/spectral_ncc.h"
#include "tracking/dense_linearization.h"
#include "tracking/frame_mosaic_warp.h"
#include "tracking/predicted_view.h"
#include "tracking/view_blur.h"

namespace fleetloc::tracking {

using geometry::Pose2;
using geometry::Difference;
using geometry::PoseWithCovariance;

namespace {

// One selected frame pixel: its level coordinates, normalized value, and its level-0 offset from
// the principal point (for the rotation column of the Jacobian).
struct PixelPoint {
  float u = 0, v = 0;
  float value = 0;
  float du0 = 0, dv0 = 0;
};

cv::Rect GrownBy(const cv::Rect& rect, int margin) {
  return {rect.x - margin, rect.y - margin, rect.width + 2 * margin, rect.height + 2 * margin};
}

double Median(std::vector<float> values) {
  if (values.empty()) return 0.0;
  const auto mid = values.begin() + values.size() / 2;
  std::nth_element(values.begin(), mid, values.end());
  return *mid;
}

// Pixels near something the mosaic cannot have: where the frame's local contrast is far above
// the floor's typical one (debris, tyre marks, dust edges, shadow edges). Local normalization
// would squash such an occluder to the floor's range, where no robust weight could tell it from
// texture, so it is masked before it is normalized. `ratio` is relative to the frame's median
// local standard deviation, so the rule holds on plain and rich floors alike. Returns CV_8U,
// non-zero where pixels must not be used.
cv::Mat OccluderMask(const cv::Mat& image, int window, double ratio) {
  cv::Mat f, mean, mean_sq;
  image.convertTo(f, CV_32F);
  cv::boxFilter(f, mean, CV_32F, {window, window});
  cv::boxFilter(f.mul(f), mean_sq, CV_32F, {window, window});
  cv::Mat variance = mean_sq - mean.mul(mean);
  std::vector<float> samples;
  for (int y = 0; y < variance.rows; y += 4) {
    for (int x = 0; x < variance.cols; x += 4) samples.push_back(variance.at<float>(y, x));
  }
  const double median_variance = std::max(1e-3, Median(samples));
  cv::Mat mask = variance > ratio * ratio * median_variance;
  cv::dilate(mask, mask, cv::getStructuringElement(cv::MORPH_RECT, {window, window}));
  return mask;
}

Eigen::Matrix3d RotationBlock(const Pose2& pose) { return geometry::ComposeJacobianB(pose); }

// pose ⊕ q⁻¹ with q in (level-0 px, px, rad).
Pose2 ApplyStep(const Pose2& pose, const Eigen::Vector3d& q_px, double resolution_m) {
  const Pose2 q{q_px.x() * resolution_m, q_px.y() * resolution_m, q_px.z()};
  return pose * q.Inverse();
}

// Largest 1-sigma displacement (level-0 px) over the frame corners under `covariance`.
double CornerSigmaPx(const geometry::CameraModel& camera, const PoseWithCovariance& pose) {
  double worst = 0.0;
  for (int corner = 0; corner < 4; ++corner) {
    const Eigen::Vector2d px((corner & 1) * camera.width_px, (corner >> 1) * camera.height_px);
    const Eigen::Matrix<double, 2, 3> j =
        geometry::PointJacobian(pose.pose, camera.PixelToGround(px));
    const Eigen::Matrix2d cov = j * pose.covariance * j.transpose();
    worst = std::max(worst,
                     Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(cov).eigenvalues().maxCoeff());
  }
  return std::sqrt(worst) / camera.resolution_m;
}

}  // namespace

// The normalized mosaic block a level reads, and how continuous mosaic coordinates index it.
struct DirectAligner::MosaicBlock {
  cv::Mat texels;  // CV_32FC4: value, d/dx, d/dy (central differences, per level pixel), 0
  cv::Rect rect;   // level pixels
  cv::Size level_size;

  // Bilinear value and gradient (out[0..2]) at continuous level coordinates; false outside the
  // block or the mosaic. The three channels are interpolated together from one interleaved
  // texel, a quarter of the memory traffic of three planes.
  bool Sample(float x, float y, float out[3]) const {
    if (x < 0.5f || y < 0.5f || x > level_size.width - 0.5f || y > level_size.height - 0.5f) {
      return false;
    }
    const float bx = x - 0.5f - rect.x, by = y - 0.5f - rect.y;
    const int x0 = static_cast<int>(std::floor(bx)), y0 = static_cast<int>(std::floor(by));
    if (x0 < 0 || y0 < 0 || x0 + 1 >= texels.cols || y0 + 1 >= texels.rows) return false;
    const float fx = bx - x0, fy = by - y0;
    const float* r0 = texels.ptr<float>(y0) + 4 * x0;
    const float* r1 = texels.ptr<float>(y0 + 1) + 4 * x0;
    for (int c = 0; c < 3; ++c) {
      const float top = r0[c] + fx * (r0[c + 4] - r0[c]);
      const float bottom = r1[c] + fx * (r1[c + 4] - r1[c]);
      out[c] = top + fy * (bottom - top);
    }
    return true;
  }
};

struct DirectAligner::Level {
  int level = 0;
  cv::Mat normalized;  // CV_32F, the frame at this level, locally normalized
  cv::Mat searched;    // the same with occluders set to 0 (the floor's mean), for the search
  int border = 0;      // pixels whose normalization window was clipped
  std::vector<PixelPoint> points;
};

// The level's pixels whose normalization window lies wholly in the frame.
cv::Rect DirectAligner::InnerRect(const Level& level) {
  const int b = level.border;
  return {b, b, level.normalized.cols - 2 * b, level.normalized.rows - 2 * b};
}

DirectAligner::DirectAligner(const DirectAlignOptions& options, const geometry::CameraModel& camera,
                             NormalizedMosaic* mosaic)
    : options_(options), camera_(camera), mosaic_(mosaic) {
  const int shorter = std::min(camera.width_px, camera.height_px);
  while (levels_ < mosaic->layout().levels && (shorter >> levels_) >= options.coarsest_side_px) {
    ++levels_;
  }
  const long long pixels = static_cast<long long>(camera.width_px) * camera.height_px;
  finest_level_ = std::min(options.min_finest_level, levels_ - 1);
  while (finest_level_ + 1 < levels_ &&
         (pixels >> (2 * (finest_level_ + 1))) >= options.finest_level_pixels) {
    ++finest_level_;
  }
}

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
    level.normalized = mosaic_->Normalize(image, l);
    level.border = mosaic_->MarginAt(l);
    const cv::Mat occluded = OccluderMask(image, window, options_.occluder_contrast_ratio);
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

// The level the search starts at: at least one above the finest (a wider window at a finer level
// holds more chance peaks: measured at 320×240 on a plain dusty floor, searching at 160×120 left
// 15 % of the frames ambiguous, at 80×60 3 %), and the finest of those whose image has at most
// search_level_pixels (the search is then cheap, and every coarser level holds less of a weak
// floor's texture), or coarser while the prediction's 3-sigma would exceed max_search_px there.
int DirectAligner::SearchLevel(double sigma_px) const {
  const long long pixels = static_cast<long long>(camera_.width_px) * camera_.height_px;
  int level = std::min(finest_level_ + 1, levels_ - 1);
  while (level + 1 < levels_ &&
         ((pixels >> (2 * level)) > options_.search_level_pixels ||
          options_.search_sigma_multiple * sigma_px / (1 << level) > options_.max_search_px)) {
    ++level;
  }
  return level;
}

// Exhaustive normalized correlation of the level's frame over a ±r window of the mosaic view
// rendered at `pose`: the best shift's pose, its correlation and the second peak's ratio to it.
DirectAligner::SearchHit DirectAligner::SearchAt(const Level& level,
                                                 const imaging::SpectralNcc& frame_ncc,
                                                 const Pose2& pose, int r) const {
  const cv::Rect inner = InnerRect(level);
  const FrameMosaicWarp warp =
      FrameMosaicWarp::For(pose, camera_, mosaic_->layout().geo).AtLevel(level.level);
  const cv::Mat view = RenderNormalizedView(mosaic_, GrownBy(inner, r), warp, level.level);
  const cv::Mat surface = frame_ncc.Surface(view);
  SearchHit hit;
  cv::Point best_at;
  cv::minMaxLoc(surface, nullptr, &hit.correlation, nullptr, &best_at);
  cv::Mat off_peak(surface.size(), CV_8U, cv::Scalar(255));
  cv::circle(off_peak, best_at, options_.peak_exclusion_px, cv::Scalar(0), cv::FILLED);
  double second = 0.0;
  cv::minMaxLoc(surface, nullptr, &second, nullptr, nullptr, off_peak);
  hit.peak_ratio = hit.correlation > 0.0 ? std::max(0.0, second) / hit.correlation : 1.0;
  cv::Scalar mean, spread;
  cv::meanStdDev(surface, mean, spread, off_peak);
  hit.peak_z = spread[0] > 0.0 ? (hit.correlation - mean[0]) / spread[0] : 0.0;
  // The frame's content sits at +shift in the view: the camera moved by shift (level px), which
  // is −shift_y, −shift_x in camera_ground axes.
  const double step_m = camera_.resolution_m * (1 << level.level);
  const Eigen::Vector2d shift(best_at.x - r, best_at.y - r);
  hit.pose = pose * Pose2{-shift.y() * step_m, -shift.x() * step_m, 0.0};
  return hit;
}

// The coarse search over the prediction's window: at the predicted heading, and when that finds
// no clear peak and the heading is uncertain enough to misalign the level's frame edges by a
// pixel, at headings spread over ±3 sigma too (a frame turned against the view correlates
// weakly everywhere; measured on fast runs over coarse asphalt: a prediction 34 px and 1.8° off
// gave an ambiguous peak at the predicted heading).
Pose2 DirectAligner::CoarseSearch(const Level& level, const PoseWithCovariance& prior,
                                  const Pose2& start, DirectAlignment* out) const {
  const double radius =
      options_.search_sigma_multiple * CornerSigmaPx(camera_, prior) / (1 << level.level);
  if (radius <= options_.search_above_px) return start;
  const int r = std::min(options_.max_search_px, static_cast<int>(std::ceil(radius)) + 1);
  out->searched = true;
  const cv::Rect inner = InnerRect(level);
  const imaging::SpectralNcc frame_ncc(level.searched(inner), GrownBy(inner, r).size());
  int searches = 1;
  SearchHit best = SearchAt(level, frame_ncc, start, r);
  // A clear peak, or a significant and distinct one, has located the frame: the alignment then
  // fits the heading too. (Significant but only unambiguous is not enough: at 320×240 under
  // `all`, peaks at z 10–14 with a second peak at 0.25–0.28 of them ended 0.8 px off or were
  // refused, where one heading step further gave z 21–23 and 0.12.)
  const bool clear = (best.correlation >= options_.min_strong_correlation &&
                      best.peak_ratio <= options_.max_weak_peak_ratio) ||
                     (options_.significant_peak_ends_search &&
                      best.peak_z >= options_.min_significant_peak_z &&
                      best.peak_ratio <= options_.max_distinct_peak_ratio);
  const double half_diagonal = 0.5 * std::hypot(level.normalized.cols, level.normalized.rows);
  const double heading_3sigma = 3.0 * std::sqrt(std::max(0.0, prior.covariance(2, 2)));
  const int steps = std::min(options_.max_heading_steps,
                             static_cast<int>(std::floor(heading_3sigma * half_diagonal)));
  if (!clear && steps >= 1) {
    // The correlation rises towards the true heading: one step each side, then onwards in the
    // better direction while it keeps rising (measured under fast turns: the best heading is
    // almost always one step off the prediction, so this costs 2–3 searches instead of 2·steps).
    const auto at = [&](int k) {
      ++searches;
      return SearchAt(level, frame_ncc, start * Pose2{0.0, 0.0, k * heading_3sigma / steps}, r);
    };
    const SearchHit minus = at(-1), plus = at(1);
    const int direction = plus.correlation >= minus.correlation ? 1 : -1;
    SearchHit next = direction > 0 ? plus : minus;
    for (int k = direction; next.correlation > best.correlation; k += direction) {
      best = next;
      if (std::abs(k) >= steps) break;
      next = at(k + direction);
    }
  }
  out->peak_ratio = best.peak_ratio;
  out->peak_z = best.peak_z;
  out->searches = searches;
  return best.pose;
}

// Why a fit cannot be trusted, or "" (see DirectAlignOptions' validation).
const char* DirectAligner::Verdict(const DirectAlignment& fit, bool prediction_confirms) const {
  const DirectAlignOptions& o = options_;
  if (fit.reason[0] != '\0') return fit.reason;
  if (fit.sigma_px > o.max_sigma_px) return "weakly constrained";
  if (fit.correlation < o.min_correlation) return "no correlation at the finest level";
  const double ratio = fit.searched ? fit.peak_ratio : 0.0;
  const bool clear_peak = fit.searched && fit.coarse_correlation >= o.min_strong_correlation &&
                          fit.peak_ratio <= o.max_clear_peak_ratio;
  // A significant peak locates the frame; the aligned frame must also correlate clearly, or the
  // fit may sit in the right basin but off by a pixel (measured: plain polished concrete at
  // 320×240 under `all`, peaks at 9–15 standard deviations, fits correlating 0.16–0.27, 0.1–1.3 px
  // off with a claimed sigma of 0.03–0.15 px).
  const bool significant = fit.searched && fit.peak_z >= o.min_significant_peak_z &&
                           fit.correlation >= o.min_significant_correlation;
  const bool distinct = clear_peak || significant ||
                        (fit.coarse_correlation >= o.min_distinct_correlation &&
                         ratio <= o.max_distinct_peak_ratio);
  const double max_chi2 = distinct ? o.max_distinct_prior_chi2 : o.max_prior_chi2;
  // Strong at the search level, or at the finest level where a weak floor's texture lives (a
  // coarse search peak that is not ambiguous, then a high correlation once aligned).
  const bool strong = (significant && fit.prior_chi2 <= max_chi2) ||
                      (fit.coarse_correlation >= o.min_strong_correlation &&
                       ratio <= o.max_strong_peak_ratio && fit.prior_chi2 <= max_chi2) ||
                      (fit.correlation >= o.min_fine_strong_correlation &&
                       ratio <= o.max_weak_peak_ratio && fit.prior_chi2 <= o.max_prior_chi2);
  const bool weak = prediction_confirms && fit.coarse_correlation >= o.min_weak_correlation &&
                    ratio <= o.max_weak_peak_ratio && fit.prior_chi2 <= o.max_weak_prior_chi2;
  if (strong || weak) return "";
  if (fit.prior_chi2 > max_chi2) return "inconsistent with the prediction";
  if (ratio > o.max_weak_peak_ratio) return "ambiguous coarse peak";
  return fit.coarse_correlation < o.min_weak_correlation
             ? "low correlation"
             : "weak fit the prediction does not confirm";
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

// Residuals, robust weights and the weighted normal equations of `level` at `pose` (sigma ≤ 0:
// estimated from the residuals' MAD), with the fit's quality and the per-block scores the
// sandwich covariance needs.
Linearization DirectAligner::Linearize(const Level& level, const MosaicBlock& source,
                                       const Pose2& pose, double sigma, double gain) const {
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
  std::vector<float> residuals(n);
  std::vector<Eigen::Vector3f> jacobians(n);
  std::vector<char> valid(n);
  std::vector<float> values(n);  // the view at each point
  double stv = 0, svv = 0;
  for (size_t i = 0; i < n; ++i) {
    const PixelPoint& p = level.points[i];
    const Eigen::Vector2f m = linear * Eigen::Vector2f(p.u, p.v) + offset;
    float sample[3];
    valid[i] = source.Sample(m.x(), m.y(), sample);
    if (!valid[i]) continue;
    values[i] = sample[0];
    stv += p.value * sample[0], svv += sample[0] * sample[0];
    const Eigen::Vector2f g = to_frame * Eigen::Vector2f(sample[1], sample[2]);
    jacobians[i] =
        Eigen::Vector3f(-g.y() * scale, -g.x() * scale, (g.x() * p.dv0 - g.y() * p.du0) * scale);
  }
  Linearization lin;
  lin.gain = gain > 0 ? gain : LeastSquaresGain(stv, svv);
  std::vector<float> magnitudes;
  magnitudes.reserve(n);
  for (size_t i = 0; i < n; ++i) {
    if (!valid[i]) continue;
    residuals[i] = level.points[i].value - static_cast<float>(lin.gain) * values[i];
    jacobians[i] *= static_cast<float>(lin.gain);
    magnitudes.push_back(std::abs(residuals[i]));
  }
  lin.points = static_cast<int>(magnitudes.size());
  if (lin.points < 3) return lin;
  lin.sigma = sigma > 0 ? sigma : std::max(1e-3, 1.4826 * Median(magnitudes));
  const double cutoff = options_.tukey_c * lin.sigma;
  std::vector<Eigen::Vector3d> block_scores(kScoreBlocks * kScoreBlocks, Eigen::Vector3d::Zero());
  std::vector<int> block_counts(kScoreBlocks * kScoreBlocks, 0);
  CorrelationSums c;
  int inliers = 0;
  for (size_t i = 0; i < n; ++i) {
    if (!valid[i]) continue;
    const double w = TukeyWeight(residuals[i], cutoff);
    const PixelPoint& p = level.points[i];
    const double t = p.value, v = values[i];
    c.sw += w, c.st += w * t, c.sv += w * v, c.stt += w * t * t, c.svv += w * v * v;
    c.stv += w * t * v;
    if (w > 0.5) ++inliers;
    if (w <= 0.0) continue;
    const Eigen::Vector3d j = jacobians[i].cast<double>();
    lin.h.noalias() += w * j * j.transpose();
    lin.g.noalias() += (w * residuals[i]) * j;
    const int bx =
        std::min(kScoreBlocks - 1, static_cast<int>(p.u * kScoreBlocks / level.normalized.cols));
    const int by =
        std::min(kScoreBlocks - 1, static_cast<int>(p.v * kScoreBlocks / level.normalized.rows));
    block_scores[by * kScoreBlocks + bx] += (w * residuals[i]) * j;
    ++block_counts[by * kScoreBlocks + bx];
  }
  lin.inlier_fraction = double(inliers) / lin.points;
  lin.correlation = c.Correlation();
  lin.next_gain = c.Gain();
  lin.score_spread = ScoreSpread(block_scores, block_counts, lin.g);
  return lin;
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

DirectAlignment DirectAligner::Align(const cv::Mat& frame, const PoseWithCovariance& prior,
                                     const Pose2& start, bool prediction_confirms,
                                     bool refine_only) const {
  DirectAlignment out;
  // A refinement starts inside the finest level's basin: no search, no coarser level.
  const int search_level = refine_only ? finest_level_ : SearchLevel(CornerSigmaPx(camera_, prior));
  const bool full_resolution =
      finest_level_ > 0 && static_cast<long long>(camera_.width_px) * camera_.height_px <=
                               options_.full_resolution_below_pixels;
  const std::vector<Level> levels =
      BuildLevels(frame, full_resolution ? 0 : finest_level_, search_level);
  Pose2 pose = refine_only ? start : CoarseSearch(levels[search_level], prior, start, &out);
  Linearization final_fit;
  for (int l = search_level; l >= finest_level_; --l) {
    const Level& level = levels[l];
    if (level.points.size() < 3) continue;
    // Coarser levels only need to hand the next level a start well inside its basin.
    const double tolerance = options_.converged_px * (l == finest_level_ ? 1.0 : 5.0);
    pose = AlignLevel(level, prior, pose, tolerance, &out.iterations, &final_fit);
    out.points = final_fit.points;
    out.inlier_fraction = final_fit.inlier_fraction;
    out.correlation = final_fit.correlation;
    if (l == search_level) out.coarse_correlation = final_fit.correlation;
  }
  Combine(final_fit, prior, pose, &out);
  out.reason = Verdict(out, prediction_confirms);
  out.valid = out.reason[0] == '\0';
  if (out.valid && full_resolution && levels[0].points.size() >= 3) {
    RefineAtFullResolution(levels[0], prior, pose, &out);
  }
  return out;
}

// A validated fit of a small frame, refined at full resolution: kept when it converges within half
// a pixel of the validated pose and its own correlation holds (the validation stays the coarser
// level's, where lens blur and noise differ less from the mosaic).
void DirectAligner::RefineAtFullResolution(const Level& level, const PoseWithCovariance& prior,
                                           const Pose2& pose, DirectAlignment* out) const {
  Linearization fit;
  int iterations = 0;
  const Pose2 refined = AlignLevel(level, prior, pose, options_.converged_px, &iterations, &fit,
                                   options_.fit_contrast);
  DirectAlignment candidate = *out;
  Combine(fit, prior, refined, &candidate);
  const Eigen::Vector3d moved = Difference(candidate.posterior.pose, out->posterior.pose);
  const double moved_px = moved.head<2>().norm() / camera_.resolution_m;
  out->iterations += iterations;
  if (candidate.reason[0] != '\0' || moved_px > 0.5 || fit.correlation < options_.min_correlation) {
    return;
  }
  out->posterior = candidate.posterior;
  out->measurement = candidate.measurement;
  out->sigma_px = candidate.sigma_px;
  out->prior_chi2 = candidate.prior_chi2;
}

// Per row of `inner`, the columns (relative to inner.x) whose pixel and its gradient neighbours
// fall inside the mosaic, with a pixel to spare, when the camera is at `pose`.
std::vector<cv::Range> DirectAligner::SpansInMosaic(const Pose2& pose, const cv::Rect& inner) const {
  const mosaic::MosaicLayout& layout = mosaic_->layout();
  constexpr double kSpare = 3.0;
  const geometry::ConvexPolygon mosaic_in_frame =
      MosaicInFrame(FrameMosaicWarp::For(pose, camera_, layout.geo), layout.width_px,
                    layout.height_px, kSpare);
  std::vector<cv::Range> spans(inner.height);
  for (int y = 0; y < inner.height; ++y) {
    const auto [lo, hi] = geometry::SpanAtY(mosaic_in_frame, inner.y + y + 0.5);
    spans[y].start = lo > hi ? 0 : std::max(0, static_cast<int>(std::ceil(lo - 0.5)) - inner.x);
    spans[y].end = lo > hi ? 0 : std::min(inner.width, static_cast<int>(std::floor(hi - 0.5)) + 1 - inner.x);
  }
  return spans;
}

// Every pixel of the frame at full resolution, from a pose already within a fraction of a pixel
// (see DirectAligner::Polish).
DirectAlignment DirectAligner::Polish(const cv::Mat& frame, const PoseWithCovariance& prior,
                                      const Pose2& start, double view_blur_px) const {
  DirectAlignment out;
  const int b = mosaic_->MarginAt(0);
  const cv::Rect inner(b, b, frame.cols - 2 * b, frame.rows - 2 * b);
  const mosaic::MosaicLayout& layout = mosaic_->layout();
  const std::vector<cv::Range> spans = SpansInMosaic(start, inner);
  int points = 0;
  for (const cv::Range& span : spans) points += std::max(0, span.end - span.start);
  if (points < inner.area() / 4) {
    out.reason = "frame mostly outside the mosaic";
    return out;
  }
  const cv::Mat normalized = mosaic_->Normalize(frame, 0);
  const cv::Rect view_rect(inner.x - 1, inner.y - 1, inner.width + 2, inner.height + 2);
  const Eigen::Vector2d principal(camera_.cx_px, camera_.cy_px);
  // The view blurred to the frame's blur, estimated at the start (see tracking/view_blur.h).
  double blur = std::max(0.0, view_blur_px);
  if (view_blur_px < 0 && options_.max_view_blur_px > 0) {
    const int m = BlurMarginPx(options_.max_view_blur_px);
    const cv::Mat wide = RenderNormalizedView(mosaic_, GrownBy(view_rect, m),
                                              FrameMosaicWarp::For(start, camera_, layout.geo), 0);
    blur = BestViewBlur(normalized, wide, m, inner, spans, options_.max_view_blur_px,
                        options_.view_blur_step_px, options_.tukey_c);
  }
  out.view_blur_px = blur;
  const int m = BlurMarginPx(blur);
  const auto linearize = [&](const Pose2& pose, double sigma, double gain) {
    const cv::Mat view = BlurredView(
        RenderNormalizedView(mosaic_, GrownBy(view_rect, m),
                             FrameMosaicWarp::For(pose, camera_, layout.geo), 0),
        blur, m);
    return LinearizeWholeFrame(normalized, view, inner, spans, principal, options_.tukey_c, sigma,
                               gain);
  };
  Linearization fit;
  const Pose2 pose = GaussNewton(linearize, 0, options_.polish_iterations, prior, start,
                                 options_.converged_px, &out.iterations, &fit,
                                 options_.fit_contrast);
  out.points = fit.points;
  out.correlation = out.coarse_correlation = fit.correlation;
  out.inlier_fraction = fit.inlier_fraction;
  Combine(fit, prior, pose, &out);
  const double moved_px =
      Difference(out.posterior.pose, start).head<2>().norm() / camera_.resolution_m;
  if (out.reason[0] == '\0') {
    if (moved_px > options_.max_polish_shift_px) {
      out.reason = "polish moved too far";
    } else if (fit.correlation < options_.min_polish_correlation) {
      out.reason = "polish does not correlate";
    } else if (out.sigma_px > options_.max_sigma_px) {
      out.reason = "weakly constrained";
    }
  }
  out.valid = out.reason[0] == '\0';
  return out;
}

// The image's own estimate and honest covariance from the finest level's linearization, fused
// with the prediction. The covariance is the sandwich H⁻¹·M·H⁻¹ over blocks of the frame (M: the
// spread of the blocks' score sums), which stays honest when residuals are correlated over
// occluders, blur or normalization windows, plus the independent-residual term σ²·H⁻¹.
void DirectAligner::Combine(const Linearization& fit, const PoseWithCovariance& prior,
                            const Pose2& pose, DirectAlignment* out) const {
  const double res = camera_.resolution_m;
  const Eigen::Matrix3d to_px = Eigen::Vector3d(res, res, 1.0).asDiagonal();
  Eigen::LDLT<Eigen::Matrix3d> h(fit.h);
  if (fit.points < 3 || h.info() != Eigen::Success || !(h.vectorD().array() > 0).all()) {
    out->reason = "no image information";
    out->posterior = prior;
    out->sigma_px = 1e9;
    return;
  }
  const Eigen::Matrix3d h_inv = h.solve(Eigen::Matrix3d::Identity());
  const Eigen::Vector3d q_image = -h_inv * fit.g;  // image-only optimum, from `pose`
  const Eigen::Matrix3d cov_q = h_inv * fit.score_spread * h_inv + fit.sigma * fit.sigma * h_inv;
  const Eigen::Matrix3d info_q = cov_q.inverse();
  const Eigen::Matrix3d bs = RotationBlock(pose) * to_px;
  const Eigen::Matrix3d prior_information = prior.covariance.inverse();
  const Eigen::Matrix3d hp = bs.transpose() * prior_information * bs;
  const Eigen::Vector3d gp = bs.transpose() * prior_information * Difference(pose, prior.pose);
  const Eigen::Vector3d q = (info_q + hp).ldlt().solve(info_q * q_image + gp);
  // Map covariance of the image estimate: map delta = −B·S·q.
  const Eigen::Matrix3d image_cov = bs * cov_q * bs.transpose();
  out->measurement = {ApplyStep(pose, q_image, res), image_cov};
  out->posterior = {ApplyStep(pose, q, res), (image_cov.inverse() + prior_information).inverse()};
  out->sigma_px = std::sqrt(
      std::max(0.0, Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(cov_q.topLeftCorner<2, 2>())
                        .eigenvalues()
                        .maxCoeff()));
  const Eigen::Vector3d innovation = Difference(out->measurement.pose, prior.pose);
  out->prior_chi2 = innovation.dot((prior.covariance + image_cov).ldlt().solve(innovation));
  if (!out->posterior.pose.ToVector().allFinite() || !out->posterior.covariance.allFinite()) {
    out->reason = "diverged";
  }
}

}  // namespace fleetloc::tracking
