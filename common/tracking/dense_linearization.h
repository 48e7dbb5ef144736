// The robust normal equations of the dense alignment (tracking/direct_aligner.h), and the
// whole-frame form used by the full-resolution polish: every pixel of the frame against a mosaic
// view rendered at the current pose, in one vectorized pass, because on noisy frames the pose's
// precision grows with the number of pixels used (issue 15: at 640×480 with 4 DN read noise the
// templates, about a fifth of the frame, reach 0.013–0.018 px where a whole-frame fit reaches
// 0.006–0.008).
#pragma once

#include <Eigen/Core>
#include <array>
#include <opencv2/core.hpp>
#include <vector>

namespace fleetloc::tracking {

// Sums over the pixels of one level at one pose. The increment q is in level-0 px, px, rad; the
// sums are not yet scaled by the residual variance.
struct Linearization {
  Eigen::Matrix3d h = Eigen::Matrix3d::Zero();             // Σ w·J·Jᵀ
  Eigen::Vector3d g = Eigen::Vector3d::Zero();             // Σ w·J·r
  Eigen::Matrix3d score_spread = Eigen::Matrix3d::Zero();  // Σ over blocks of score outer products
  double sigma = 0.0;                                      // robust residual scale
  // The frame's contrast against the view: residuals are t − gain·v. `next_gain` is its weighted
  // least-squares estimate from this pass's weights, for the next pass.
  double gain = 1.0, next_gain = 1.0;
  double correlation = 0.0, inlier_fraction = 0.0;
  int points = 0;
  // Σ p·ψ′·(j0² + j1²), ψ′ the slope of the Tukey influence ψ at each pixel's residual: the robust
  // loss's own curvature over the translation, where h weighs each pixel by w = ψ/r instead. Summed
  // by the whole-frame linearization only (`robust_curvature_summed`).
  double robust_curvature = 0.0;
  bool robust_curvature_summed = false;
  // The curvature the fit's steps met along their translation over h's (SecantCurvature); 0: not
  // measured.
  double secant_curvature = 0.0;
};

// Weighted sums of the frame values t and mosaic values v, for the weighted correlation.
struct CorrelationSums {
  double sw = 0, st = 0, sv = 0, stt = 0, svv = 0, stv = 0;
  double Correlation() const;
  // The weighted least-squares contrast of t against v (t ≈ gain·v; both are zero-mean
  // normalized images), clamped to a sane range; 1 when v carries nothing.
  double Gain() const;
};

// Local normalization divides each pixel by its neighbourhood's standard deviation. In a noisy
// frame that deviation is mostly noise, so the frame's normalized texture has a fraction of the
// clean mosaic's contrast; fitted against the view at full contrast, the (1 − contrast)·v part of
// every residual pulls the pose wherever the robust weights change (occluder edges), a bias that
// differs from frame to frame. Residuals against gain·v, with the gain fitted, remove it.
inline constexpr double kMinGain = 0.05, kMaxGain = 2.0;

// Unweighted least-squares contrast of t against v over samples: a starting gain.
double LeastSquaresGain(double stv, double svv);

// Residuals correlate within a block of the frame (blur, normalization windows, occluders) but
// hardly across blocks: the frame is cut into kScoreBlocks² blocks and the spread of their score
// sums gives the sandwich covariance's middle term.
inline constexpr int kScoreBlocks = 8;

// Completes `lin` from sums taken over its pixels (h's upper triangle, g, points already set):
// h's lower triangle, the correlation and next gain from `c`, the inlier fraction and the score
// spread of the blocks.
void FinishLinearization(const CorrelationSums& c, double inliers,
                         const std::vector<Eigen::Vector3d>& block_scores,
                         const std::vector<int>& block_counts, Linearization* lin);

// The image-only covariance of the step q (level-0 px, px, rad) from `fit` and h⁻¹.
// A whole-frame fit takes the M-estimator's sandwich A⁻¹·M·A⁻¹: M the spread of the blocks'
// score sums (honest where residuals correlate within a block: blur, occluders, normalization
// windows), A the robust loss's curvature. A is h scaled by the share robust_curvature / (h00 +
// h11), one number instead of a second matrix: the share is 0.80–0.84 on every stress frame
// (Gaussian residuals give 0.83 at the Tukey cut-off of 4.685 sigmas), clamped at
// kMinCurvatureShare. h⁻¹·M·h⁻¹ alone understates the spread by that share squared; with σ²·h⁻¹
// added, as before session 55, it overstated it (the 640×480 stress poses' NEES about 1 for 3 dof).
// The point linearization of the coarse-to-fine alignment keeps h⁻¹·M·h⁻¹ + σ²·h⁻¹: its
// validation thresholds (max_sigma_px, the prediction's χ², the agreement test) were set on it.
//
// The Jacobian is the view's central differences. Where the view holds detail near its pixel
// pitch (a polish above level 0, whose view is the mosaic's 2 × 2 means) they understate the
// view's true change with the pose, and h with it: the steps' secant (SecantCurvature) measured
// a median 1.1 times h along the translation at 640×480 (share and Jacobian together) where the
// share alone is 0.82, so h⁻¹·M·h⁻¹ / share² claimed 1.7 times the poses' spread. Above level 0
// the share is taken from the secant, between the ψ′ share and twice that (GaussNewton sets
// secant_curvature). At level 0 the secant is near the share on clean frames (median 0.8) and
// noisy under dust, where taking it left 21 of 3,600 poses beyond their 99.9 % bound (7 without).
Eigen::Matrix3d ImageCovariance(const Linearization& fit, const Eigen::Matrix3d& h_inv);
inline constexpr double kMinCurvatureShare = 0.25;

// The curvature along `step` (level-0 px, px, rad) from the linearization `first` at its start to
// `last` at its end, over h's: (g_last − g_first)·s / (s·h_first·s) for the step's translation s.
// 0 when s is under kMinSecantStepPx, where the change in g is mostly that of the weights.
double SecantCurvature(const Linearization& first, const Linearization& last,
                       const Eigen::Vector3d& step);
inline constexpr double kMinSecantStepPx = 0.02;

// h⁻¹·M·h⁻¹ + σ²·h⁻¹: the sandwich plus the independent-residual term. The coarse-to-fine
// alignment's covariance, and the figure the polish's window and smoothing choices compare (their
// ratios were set on it: it weighs a fit's raw residual noise, which the matching's smoothing
// lowers, against its correlated spread, which the smoothing raises).
Eigen::Matrix3d SandwichPlusIndependent(const Linearization& fit, const Eigen::Matrix3d& h_inv);

// A linearization over the pixels of pyramid level `level` (its Jacobian's translation columns per
// level pixel) re-expressed per level-0 pixel, the unit of the pose steps: those columns divided
// by 2^level.
void InLevel0Pixels(int level, Linearization* lin);

// Spread of the blocks' score sums about their share (by pixel count) of `total`, scaled by
// n/(n − 1) over the n blocks that have pixels.
Eigen::Matrix3d ScoreSpread(const std::vector<Eigen::Vector3d>& block_scores,
                            const std::vector<int>& block_counts, const Eigen::Vector3d& total);

// The pixels one level of the dense alignment uses, as arrays grouped by score block: block b's
// pixels are [block_start[b], block_start[b + 1]).
struct PointSet {
  std::vector<float> u, v;      // level coordinates (pixel centres at i + 0.5)
  std::vector<float> value;     // the normalized frame there
  std::vector<float> du0, dv0;  // level-0 offsets from the principal point (rotation column)
  std::array<int, kScoreBlocks * kScoreBlocks + 1> block_start{};
  size_t size() const { return value.size(); }
};

// The mosaic view at a PointSet's pixels: its value, and its gradient in frame axes per level-0
// pixel (the Jacobian's factors); `seen` is 1 where the pixel's view lies in the mosaic, else 0
// (and the others 0).
struct PointViews {
  std::vector<float> value, gx, gy, seen;
  PointViews() = default;
  explicit PointViews(size_t n) : value(n), gx(n), gy(n), seen(n) {}
};

// The robust normal equations over a PointSet's seen pixels, as LinearizeWholeFrame's: residuals
// t − gain·v, sigma ≤ 0 estimated from their MAD, gain ≤ 0 their least-squares contrast.
Linearization LinearizePoints(const PointSet& points, const PointViews& views, double tukey_c,
                              double sigma, double gain);

// The whole frame at level 0. `frame`: the normalized frame (CV_32F). `view`: the normalized
// mosaic rendered at the pose (CV_32F) over `inner` grown by one pixel on each side, for the
// central-difference gradient. `inner`: the frame pixels used (inside `frame`). `principal_px`:
// the principal point (the rotation column's origin). `spans`: per row of `inner`, the columns
// (relative to inner.x) whose view lies in the mosaic; empty: every column. sigma ≤ 0: estimated
// from the residuals' MAD. gain: residuals are t − gain·v; ≤ 0: estimated from a sparse grid of
// the pixels. The Jacobian takes the view's gradient (the clean mosaic's, see Linearize in
// direct_aligner.cpp), times the gain. `precision` (CV_32F, frame's size; empty: 1 everywhere):
// each pixel's residual precision relative to the others (tracking/noise_precision.h); sigma is
// then the spread of √precision·r.
Linearization LinearizeWholeFrame(const cv::Mat& frame, const cv::Mat& view, const cv::Rect& inner,
                                  const std::vector<cv::Range>& spans,
                                  const Eigen::Vector2d& principal_px, double tukey_c, double sigma,
                                  double gain = 1.0, const cv::Mat& precision = cv::Mat());

}  // namespace fleetloc::tracking
