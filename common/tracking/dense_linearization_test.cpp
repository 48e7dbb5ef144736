// The whole-frame normal equations against a known sub-pixel shift: the Gauss–Newton step finds
// it, the mosaic spans limit the pixels used, and an occluder the view lacks is weighted out.
#include "tracking/dense_linearization.h"

#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace fleetloc::tracking {
namespace {

// A smooth random texture defined everywhere: a sum of plane waves of random direction, wavelength
// 5–30 px and phase, so a shifted view is exact (no interpolation, whose sub-pixel quantization
// in cv::warpAffine would move the fixed point).
struct WaveTexture {
  struct Wave {
    double kx, ky, phase, amplitude;
  };
  std::vector<Wave> waves;

  WaveTexture() {
    cv::RNG rng(7);
    for (int i = 0; i < 40; ++i) {
      const double angle = rng.uniform(0.0, CV_PI), k = 2 * CV_PI / rng.uniform(5.0, 30.0);
      waves.push_back({k * std::cos(angle), k * std::sin(angle), rng.uniform(0.0, 2 * CV_PI),
                       rng.uniform(0.1, 0.3)});
    }
  }
  // The texture over `size` pixels, pixel (i, j) showing point (j + origin.x, i + origin.y).
  cv::Mat Render(cv::Size size, cv::Point2d origin) const {
    cv::Mat image(size, CV_32F);
    for (int y = 0; y < size.height; ++y) {
      for (int x = 0; x < size.width; ++x) {
        double value = 0;
        for (const Wave& w : waves) {
          value += w.amplitude * std::sin(w.kx * (x + origin.x) + w.ky * (y + origin.y) + w.phase);
        }
        image.at<float>(y, x) = static_cast<float>(value);
      }
    }
    return image;
  }
};

// The texture so that view pixel x shows frame point x + shift, over `inner` grown by one pixel
// (the layout LinearizeWholeFrame expects).
cv::Mat ShiftedView(const WaveTexture& texture, const cv::Rect& inner, const cv::Point2d& shift) {
  return texture.Render({inner.width + 2, inner.height + 2},
                        {inner.x - 1 + shift.x, inner.y - 1 + shift.y});
}

Eigen::Vector3d Step(const Linearization& lin) { return -lin.h.inverse() * lin.g; }

// The shift found by Gauss–Newton steps, each from a view rendered at the estimate so far (q is
// in camera_ground axes: frame x is ground −y, frame y is ground −x). One step alone overshoots
// by the central difference's underestimate of the gradient (~15 % on this texture).
// fit_gain: the frame's contrast is fitted (each step's gain from the last step's weights).
cv::Point2d SolveShift(const cv::Mat& frame, const WaveTexture& texture, const cv::Rect& inner,
                       const std::vector<cv::Range>& spans, const cv::Point2d& shift,
                       Linearization* last, bool fit_gain = false) {
  cv::Point2d estimate(0, 0);
  double gain = fit_gain ? 0.0 : 1.0;
  for (int it = 0; it < 4; ++it) {
    *last = LinearizeWholeFrame(frame, ShiftedView(texture, inner, shift - estimate), inner, spans,
                                {100.0, 80.0}, 4.685, 0.0, gain);
    if (fit_gain) gain = last->next_gain;
    const Eigen::Vector3d q = Step(*last);
    EXPECT_NEAR(q.z(), 0.0, 1e-3);
    estimate += cv::Point2d(-q.y(), -q.x());
  }
  return estimate;
}

TEST(LinearizeWholeFrame, GaussNewtonStepsRecoverASubPixelShift) {
  const WaveTexture texture;
  const cv::Mat image = texture.Render({200, 160}, {0, 0});
  const cv::Rect inner(10, 10, 180, 140);
  const cv::Point2d shift(0.3, -0.2);
  Linearization lin;
  const cv::Point2d found = SolveShift(image, texture, inner, {}, shift, &lin);
  EXPECT_EQ(lin.points, inner.area());
  EXPECT_NEAR(found.x, shift.x, 0.005);
  EXPECT_NEAR(found.y, shift.y, 0.005);
  EXPECT_GT(lin.correlation, 0.99);
}

TEST(LinearizeWholeFrame, UsesOnlyTheSpansInsideTheMosaic) {
  const WaveTexture texture;
  const cv::Mat image = texture.Render({200, 160}, {0, 0});
  const cv::Rect inner(10, 10, 180, 140);
  const std::vector<cv::Range> spans(inner.height, cv::Range(40, 120));
  Linearization lin;
  const cv::Point2d found = SolveShift(image, texture, inner, spans, {0.25, 0.1}, &lin);
  EXPECT_EQ(lin.points, 80 * inner.height);
  EXPECT_NEAR(found.x, 0.25, 0.005);
  EXPECT_NEAR(found.y, 0.1, 0.005);
}

TEST(LinearizeWholeFrame, AnOccluderTheViewLacksIsWeightedOut) {
  const WaveTexture texture;
  const cv::Mat clean = texture.Render({200, 160}, {0, 0});
  const cv::Rect inner(10, 10, 180, 140);
  cv::Mat occluded = clean.clone();
  occluded(cv::Rect(30, 30, 60, 50)).setTo(40.0f);  // a bright blob over 12 % of the pixels
  Linearization lin;
  const cv::Point2d found = SolveShift(occluded, texture, inner, {}, {-0.2, 0.35}, &lin);
  EXPECT_LT(lin.inlier_fraction, 0.9);
  EXPECT_NEAR(found.x, -0.2, 0.01);
  EXPECT_NEAR(found.y, 0.35, 0.01);
}

// A noisy frame, normalized, shows the floor at a fraction of the mosaic's contrast, and an
// occluder the mosaic lacks shows none. Fitting the view at full contrast leaves (1 − contrast)·v
// in every residual, which the occluder's edge turns into a pull on the pose; fitting the gain
// removes it and lets the robust weights drop the occluder.
TEST(LinearizeWholeFrame, AFittedGainRemovesTheBiasOfAFrameAtLowContrast) {
  const WaveTexture texture;
  const cv::Rect inner(10, 10, 180, 140);
  cv::Mat frame = 0.5 * texture.Render({200, 160}, {0, 0});
  cv::Mat noise(frame.size(), CV_32F);
  cv::RNG(3).fill(noise, cv::RNG::NORMAL, 0.0, 0.02);
  frame += noise;
  frame(cv::Rect(20, 20, 90, 70)).setTo(0.0f);  // a flat occluder over a quarter of the frame
  const cv::Point2d shift(0.3, -0.2);
  Linearization fixed, fitted;
  const cv::Point2d with_fixed = SolveShift(frame, texture, inner, {}, shift, &fixed, false);
  const cv::Point2d with_fitted = SolveShift(frame, texture, inner, {}, shift, &fitted, true);
  EXPECT_NEAR(fitted.gain, 0.5, 0.05);
  EXPECT_LT(fitted.inlier_fraction, 0.85);  // the occluder is weighted out
  EXPECT_NEAR(with_fitted.x, shift.x, 0.01);
  EXPECT_NEAR(with_fitted.y, shift.y, 0.01);
  const double error_fixed = std::hypot(with_fixed.x - shift.x, with_fixed.y - shift.y);
  const double error_fitted = std::hypot(with_fitted.x - shift.x, with_fitted.y - shift.y);
  EXPECT_LT(error_fitted, 0.5 * error_fixed) << "fixed gain: " << error_fixed;
}

// Every pixel of `inner` as a PointSet, grouped in LinearizeWholeFrame's score blocks, with the
// view's value and central-difference gradient there (`view` laid out as LinearizeWholeFrame's).
void AllPixels(const cv::Mat& frame, const cv::Mat& view, const cv::Rect& inner,
               const cv::Point2d& principal, PointSet* points, PointViews* views) {
  std::vector<std::vector<int>> by_block(kScoreBlocks * kScoreBlocks);
  for (int y = 0; y < inner.height; ++y) {
    for (int x = 0; x < inner.width; ++x) {
      const int block = (y * kScoreBlocks / inner.height) * kScoreBlocks;
      int bx = 0;
      while ((bx + 1) * inner.width / kScoreBlocks <= x) ++bx;
      by_block[block + bx].push_back(y * inner.width + x);
    }
  }
  *views = PointViews(static_cast<size_t>(inner.area()));
  for (int b = 0; b < kScoreBlocks * kScoreBlocks; ++b) {
    points->block_start[b + 1] = points->block_start[b] + static_cast<int>(by_block[b].size());
    for (int k : by_block[b]) {
      const int x = k % inner.width, y = k / inner.width;
      const size_t i = points->value.size();
      points->u.push_back(x + 0.5f);
      points->v.push_back(y + 0.5f);
      points->value.push_back(frame.at<float>(inner.y + y, inner.x + x));
      points->du0.push_back(static_cast<float>(inner.x + x + 0.5 - principal.x));
      points->dv0.push_back(static_cast<float>(inner.y + y + 0.5 - principal.y));
      views->value[i] = view.at<float>(y + 1, x + 1);
      views->gx[i] = 0.5f * (view.at<float>(y + 1, x + 2) - view.at<float>(y + 1, x));
      views->gy[i] = 0.5f * (view.at<float>(y + 2, x + 1) - view.at<float>(y, x + 1));
      views->seen[i] = 1.0f;
    }
  }
}

// Mean over `trials` noisy frames of the fitted shift's squared error in the sigmas of the
// covariance `covariance(fit, h⁻¹)` claims for it: 2 (two dof) when that covariance is honest. The
// noise is Gaussian, blurred by `blur_px` (0: none) and scaled to `noise_sigma`. Each fit takes
// three robust Gauss–Newton steps from the truth, the claim from the last linearization, as the
// polish does; the view at a shift e is its first-order expansion v − e·∇v (the errors are
// hundredths of a pixel), so the test renders the texture once.
template <typename Covariance>
double MeanPositionNees(double noise_sigma, double blur_px, int trials, Covariance covariance) {
  const WaveTexture texture;
  const cv::Rect inner(10, 10, 180, 140);
  const cv::Mat clean = texture.Render({200, 160}, {0, 0});
  const cv::Mat view = ShiftedView(texture, inner, {0, 0});
  cv::Mat gx, gy;
  cv::Sobel(view, gx, CV_32F, 1, 0, 3, 1.0 / 8);
  cv::Sobel(view, gy, CV_32F, 0, 1, 3, 1.0 / 8);
  cv::RNG rng(11);
  double sum = 0;
  for (int i = 0; i < trials; ++i) {
    cv::Mat noise(clean.size(), CV_32F);
    rng.fill(noise, cv::RNG::NORMAL, 0.0, 1.0);
    if (blur_px > 0) cv::GaussianBlur(noise, noise, {}, blur_px);
    cv::Scalar mean, deviation;
    cv::meanStdDev(noise, mean, deviation);
    const cv::Mat frame = clean + noise * (noise_sigma / deviation[0]);
    cv::Point2d e(0, 0);
    Linearization fit;
    for (int step = 0; step < 3; ++step) {
      const cv::Mat shifted = view - e.x * gx - e.y * gy;
      fit = LinearizeWholeFrame(frame, shifted, inner, {}, {100.0, 80.0}, 4.685, 0.0, 1.0);
      const Eigen::Vector3d q = Step(fit);
      e += cv::Point2d(-q.y(), -q.x());
    }
    const Eigen::Vector2d error(-e.y, -e.x);  // in q's axes
    const Eigen::Matrix3d claimed = covariance(fit, fit.h.inverse());
    sum += error.dot(claimed.topLeftCorner<2, 2>().inverse() * error);
  }
  return sum / trials;
}

// The whole-frame fit's covariance is the M-estimator's sandwich: honest under white noise and
// under noise correlated over neighbouring pixels (a blur), which the blocks' score spread counts.
// The sandwich plus the independent-residual term, the covariance before session 55, claims
// nearly twice the spread of the white-noise fits.
TEST(ImageCovariance, AWholeFrameFitsCovarianceMatchesTheSpreadOfItsEstimates) {
  const double white = MeanPositionNees(0.3, 0.0, 300, ImageCovariance);
  const double blurred = MeanPositionNees(0.3, 1.5, 300, ImageCovariance);
  const double sum = MeanPositionNees(0.3, 0.0, 300, SandwichPlusIndependent);
  EXPECT_NEAR(white, 2.0, 0.4);  // measured 2.28; the sandwich alone gives 3.33
  EXPECT_GT(blurred, 1.6);       // measured 2.47: the blocks' edges cut a little of the correlation
  EXPECT_LT(blurred, 2.8);
  EXPECT_LT(sum, 1.4);  // measured 1.24
}

// The view's central differences understate its change with the pose (the texture's finest
// waves are 5 px long), so a Gauss–Newton step overshoots; the secant between the linearizations
// at the step's two ends measures by how much: the first step's length over the true shift.
TEST(SecantCurvature, MeasuresByHowMuchTheJacobianUnderstatesTheViewsChange) {
  const WaveTexture texture;
  const cv::Mat frame = texture.Render({200, 160}, {0, 0});
  const cv::Rect inner(10, 10, 180, 140);
  const cv::Point2d shift(0.3, -0.2);
  const Linearization start = LinearizeWholeFrame(frame, ShiftedView(texture, inner, shift), inner,
                                                  {}, {100.0, 80.0}, 4.685, 0.0, 1.0);
  const Linearization truth = LinearizeWholeFrame(frame, ShiftedView(texture, inner, {0, 0}), inner,
                                                  {}, {100.0, 80.0}, 4.685, 0.0, 1.0);
  const Eigen::Vector3d step = Step(start);
  const Eigen::Vector3d moved(-shift.y, -shift.x, 0.0);  // the true step, in q's axes
  const double secant = SecantCurvature(start, truth, moved);
  EXPECT_GT(secant, 1.03);  // measured 1.056
  EXPECT_NEAR(secant, step.head<2>().norm() / moved.head<2>().norm(), 0.03);
  EXPECT_EQ(SecantCurvature(start, truth, 0.5 * kMinSecantStepPx * moved / moved.norm()), 0.0);
}

// The covariance takes the secant's curvature between the ψ′ share and twice it.
TEST(ImageCovariance, TakesTheSecantsCurvatureWithinTwiceTheShare) {
  Linearization fit;
  fit.h = Eigen::Matrix3d::Identity();
  fit.score_spread = Eigen::Matrix3d::Identity();
  fit.robust_curvature = 1.6;  // a share of 0.8 of h's translation trace, 2
  fit.robust_curvature_summed = true;
  const Eigen::Matrix3d h_inv = Eigen::Matrix3d::Identity();
  EXPECT_NEAR(ImageCovariance(fit, h_inv)(0, 0), 1 / (0.8 * 0.8), 1e-12);
  fit.secant_curvature = 1.1;
  EXPECT_NEAR(ImageCovariance(fit, h_inv)(0, 0), 1 / (1.1 * 1.1), 1e-12);
  fit.secant_curvature = 0.5;
  EXPECT_NEAR(ImageCovariance(fit, h_inv)(0, 0), 1 / (0.8 * 0.8), 1e-12);
  fit.secant_curvature = 3.0;
  EXPECT_NEAR(ImageCovariance(fit, h_inv)(0, 0), 1 / (1.6 * 1.6), 1e-12);
}

// The sparse levels' sums (LinearizePoints) over every pixel are the whole-frame sums, with an
// occluder, a fitted gain and an estimated scale: one set of equations, two layouts.
TEST(LinearizePoints, OverEveryPixelAgreesWithTheWholeFrame) {
  const WaveTexture texture;
  const cv::Rect inner(10, 10, 180, 140);
  cv::Mat frame = 0.7 * texture.Render({200, 160}, {0, 0});
  frame(cv::Rect(30, 30, 60, 50)).setTo(2.0f);
  const cv::Mat view = ShiftedView(texture, inner, {0.3, -0.2});
  const cv::Point2d principal(100.0, 80.0);
  PointSet points;
  PointViews views(0);
  AllPixels(frame, view, inner, principal, &points, &views);
  for (const double gain : {1.0, 0.0}) {
    const Linearization whole =
        LinearizeWholeFrame(frame, view, inner, {}, {principal.x, principal.y}, 4.685, 0.0, gain);
    const Linearization sparse = LinearizePoints(points, views, 4.685, whole.sigma, whole.gain);
    EXPECT_EQ(sparse.points, whole.points);
    EXPECT_NEAR(sparse.correlation, whole.correlation, 1e-5);
    EXPECT_NEAR(sparse.inlier_fraction, whole.inlier_fraction, 1e-5);
    EXPECT_NEAR(sparse.next_gain, whole.next_gain, 1e-5);
    EXPECT_LT((sparse.h - whole.h).norm(), 1e-5 * whole.h.norm());
    EXPECT_LT((sparse.g - whole.g).norm(), 1e-4 * whole.g.norm() + 1e-6);
    EXPECT_LT(sparse.inlier_fraction, 0.95);  // the occluder is weighted out in both
  }
  // The score spread shares the total out by pixel count: the whole frame counts every pixel of
  // a block, the sparse levels the pixels with weight > 0. With no pixel weighted out they agree.
  const Linearization whole =
      LinearizeWholeFrame(frame, view, inner, {}, {principal.x, principal.y}, 4.685, 1e3, 1.0);
  const Linearization sparse = LinearizePoints(points, views, 4.685, 1e3, 1.0);
  EXPECT_LT((sparse.score_spread - whole.score_spread).norm(), 1e-4 * whole.score_spread.norm());
  // Unseen pixels add nothing: half the pixels unseen, half the points.
  for (size_t i = 0; i < views.seen.size(); i += 2) {
    views.seen[i] = 0.0f;
    views.value[i] = views.gx[i] = views.gy[i] = 0.0f;
  }
  EXPECT_EQ(LinearizePoints(points, views, 4.685, 0.0, 0.0).points, inner.area() / 2);
}

}  // namespace
}  // namespace fleetloc::tracking
