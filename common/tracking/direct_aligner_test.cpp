// Dense alignment against ground truth on a real photo (tracking/test_scene.h): small and large
// prediction errors, occluders the mosaic lacks with vignetting and uneven light, a low-contrast
// floor, a frame of another floor (must be refused), and the honesty of the covariance.
#include "tracking/direct_aligner.h"

#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>

#include "mosaic/raster_source.h"
#include "tracking/test_scene.h"

namespace fleetloc::tracking {
namespace {

using geometry::Pose2;
using geometry::PoseWithCovariance;

constexpr double kRes = 0.0005;

// The scene's 160×120 camera is small: the alignment goes down to full resolution.
DirectAlignOptions SmallCameraOptions() {
  DirectAlignOptions options;
  options.min_finest_level = 0;
  return options;
}

// Options whose polish works at level 1 on the scene's camera, as on a 1280×1024 camera.
DirectAlignOptions PolishAtLevel1Options(const TestScene& scene) {
  DirectAlignOptions options = SmallCameraOptions();
  options.polish_max_level_pixels = scene.camera.width_px * scene.camera.height_px / 4;
  return options;
}

// `level0_sigma_px`: the matching's smoothing of the normalized mosaic at level 0 (the tracker's
// match_smoothing_sigma_px; 0: none).
struct Fixture {
  explicit Fixture(double level0_sigma_px = 0.0)
      : normalized(&source, 7, 16 << 20, level0_sigma_px),
        aligner(SmallCameraOptions(), scene.camera, &normalized) {}
  TestScene scene;
  mosaic::ImageRasterSource source{scene.floor, scene.geo};
  NormalizedMosaic normalized;
  DirectAligner aligner;
};

Pose2 TrueBase() { return Pose2{0.12, 0.13, 0.4} * Pose2{0.1, 0, 0}.Inverse(); }

// Camera-centre error in pixels between the fitted camera pose and the true one.
double CentreErrorPx(const TestScene& scene, const Pose2& camera, const Pose2& base) {
  const Pose2 truth = base * scene.camera.mount;
  return std::hypot(camera.x - truth.x, camera.y - truth.y) / kRes;
}

PoseWithCovariance Prior(const TestScene& scene, const Pose2& base, const Eigen::Vector3d& error,
                         const Eigen::Vector3d& sigma) {
  const Pose2 truth = base * scene.camera.mount;
  return {{truth.x + error.x(), truth.y + error.y(), truth.theta + error.z()},
          sigma.cwiseAbs2().asDiagonal()};
}

// Paints opaque blobs (bright and dark) over about `fraction` of the frame.
void Occlude(cv::Mat* frame, double fraction, cv::RNG& rng) {
  cv::Mat mask = cv::Mat::zeros(frame->size(), CV_8U);
  while (cv::countNonZero(mask) < fraction * frame->total()) {
    const cv::Point c(rng.uniform(0, frame->cols), rng.uniform(0, frame->rows));
    const cv::Size axes(rng.uniform(3, 14), rng.uniform(2, 8));
    const double angle = rng.uniform(0.0, 180.0);
    const int level = rng.uniform(0, 2) ? 235 : 25;
    cv::ellipse(*frame, c, axes, angle, 0, 360, cv::Scalar(level), cv::FILLED);
    cv::ellipse(mask, c, axes, angle, 0, 360, cv::Scalar(255), cv::FILLED);
  }
}

// Multiplies by a strong vignetting and a left-to-right light gradient.
void Shade(cv::Mat* frame) {
  cv::Mat f;
  frame->convertTo(f, CV_32F);
  for (int y = 0; y < f.rows; ++y) {
    for (int x = 0; x < f.cols; ++x) {
      const double r2 = (std::pow(x - f.cols / 2.0, 2) + std::pow(y - f.rows / 2.0, 2)) /
                        (std::pow(f.cols / 2.0, 2) + std::pow(f.rows / 2.0, 2));
      f.at<float>(y, x) *= static_cast<float>((1.0 - 0.5 * r2) * (0.7 + 0.6 * x / f.cols));
    }
  }
  f.convertTo(*frame, CV_8U);
}

TEST(DirectAligner, RecoversASmallPredictionErrorToAFractionOfAPixel) {
  Fixture f;
  const Pose2 base = TrueBase();
  const cv::Mat frame = f.scene.Render(base, 0.9, 5.0);
  const PoseWithCovariance prior =
      Prior(f.scene, base, {0.0012, -0.0009, 0.008}, {0.002, 0.002, 0.01});
  const DirectAlignment fit = f.aligner.Align(frame, prior, prior.pose);
  ASSERT_TRUE(fit.valid) << fit.reason;
  EXPECT_LT(CentreErrorPx(f.scene, fit.posterior.pose, base), 0.05);
  EXPECT_NEAR(fit.posterior.pose.theta, (base * f.scene.camera.mount).theta, 0.002);
  EXPECT_GT(fit.correlation, 0.5);
}

TEST(DirectAligner, FindsTheBasinFromAPoorPredictionByCoarseSearch) {
  Fixture f;
  const Pose2 base = TrueBase();
  const cv::Mat frame = f.scene.Render(base, 1.1, -5.0);
  // 20 px off (well outside any gradient basin), prediction sigma 8 px.
  const PoseWithCovariance prior = Prior(f.scene, base, {0.006, 0.008, 0.01}, {0.004, 0.004, 0.02});
  const DirectAlignment fit = f.aligner.Align(frame, prior, prior.pose);
  ASSERT_TRUE(fit.valid) << fit.reason;
  EXPECT_TRUE(fit.searched);
  EXPECT_GT(fit.peak_z, 8.0);
  EXPECT_LT(CentreErrorPx(f.scene, fit.posterior.pose, base), 0.1);
}

// A fit whose search peak is significant is taken at an innovation the prediction's covariance
// calls unlikely (an odometry model too confident in a fast turn), and only through that rule:
// here every other rule is set to refuse it.
TEST(DirectAligner, TakesASignificantPeakThatThePredictionDoesNotExpect) {
  Fixture f;
  const Pose2 base = TrueBase();
  const cv::Mat frame = f.scene.Render(base, 1.0, 0.0);
  const PoseWithCovariance prior = Prior(f.scene, base, {0.006, 0.008, 0.01}, {0.004, 0.004, 0.02});
  DirectAlignOptions options = SmallCameraOptions();
  options.max_prior_chi2 = options.max_weak_prior_chi2 = 0.01;
  options.max_clear_peak_ratio = 0.001;
  options.min_distinct_correlation = 0.999;
  for (const double min_z : {8.0, 1000.0}) {
    options.min_significant_peak_z = min_z;
    const DirectAligner aligner(options, f.scene.camera, &f.normalized);
    const DirectAlignment fit = aligner.Align(frame, prior, prior.pose);
    EXPECT_GT(fit.prior_chi2, options.max_prior_chi2);
    EXPECT_EQ(fit.valid, min_z == 8.0) << "z " << fit.peak_z << ": " << fit.reason;
    if (fit.valid) {
      EXPECT_LT(CentreErrorPx(f.scene, fit.posterior.pose, base), 0.1);
    }
  }
}

TEST(DirectAligner, FindsAPredictionTurnedByTwiceItsHeadingSigma) {
  Fixture f;
  const Pose2 base = TrueBase();
  const cv::Mat frame = f.scene.Render(base, 1.0, 0.0);
  // 12 px and 2.3° off, heading sigma 1.1°: the coarse search climbs over headings to the basin.
  const PoseWithCovariance prior =
      Prior(f.scene, base, {0.004, -0.004, 0.04}, {0.004, 0.004, 0.02});
  const DirectAlignment fit = f.aligner.Align(frame, prior, prior.pose);
  ASSERT_TRUE(fit.valid) << fit.reason;
  EXPECT_TRUE(fit.searched);
  EXPECT_LT(CentreErrorPx(f.scene, fit.posterior.pose, base), 0.1);
  EXPECT_LT(
      std::abs(geometry::WrapAngle(fit.posterior.pose.theta - (base * f.scene.camera.mount).theta)),
      0.001);
}

// A significant, unambiguous peak at the predicted heading ends the coarse search: the alignment
// fits the rest of the turn, as accurately as after the climb over headings it saves.
TEST(DirectAligner, ASignificantPeakEndsTheSearchAndTheAlignmentFitsTheTurn) {
  Fixture f;
  const Pose2 base = TrueBase();
  const cv::Mat frame = f.scene.Render(base, 1.0, 0.0);
  // 12 px and 0.6° off, heading sigma 1.1°: the climb would try a heading step each side.
  const PoseWithCovariance prior =
      Prior(f.scene, base, {0.004, -0.004, 0.01}, {0.004, 0.004, 0.02});
  DirectAlignOptions options = SmallCameraOptions();
  options.min_strong_correlation = 0.99;  // only significance can make the peak clear
  // The climb over whole windows, whose searches are counted (heading probes are not searches).
  options.heading_probe_px = 0;
  for (const bool ends : {true, false}) {
    options.significant_peak_ends_search = ends;
    const DirectAligner aligner(options, f.scene.camera, &f.normalized);
    const DirectAlignment fit = aligner.Align(frame, prior, prior.pose);
    ASSERT_TRUE(fit.valid) << fit.reason;
    EXPECT_GE(fit.peak_z, options.min_significant_peak_z);
    EXPECT_EQ(fit.searches == 1, ends) << fit.searches << " searches";
    EXPECT_LT(CentreErrorPx(f.scene, fit.posterior.pose, base), 0.1);
    EXPECT_LT(std::abs(geometry::WrapAngle(fit.posterior.pose.theta -
                                           (base * f.scene.camera.mount).theta)),
              0.001);
  }
}

TEST(DirectAligner, IgnoresOccludersVignettingAndUnevenLight) {
  Fixture f;
  cv::RNG rng(3);
  const Pose2 base = TrueBase();
  cv::Mat frame = f.scene.Render(base, 1.0, 0.0);
  Occlude(&frame, 0.3, rng);
  Shade(&frame);
  const PoseWithCovariance prior =
      Prior(f.scene, base, {-0.001, 0.0015, -0.01}, {0.002, 0.002, 0.01});
  const DirectAlignment fit = f.aligner.Align(frame, prior, prior.pose);
  ASSERT_TRUE(fit.valid) << fit.reason;
  EXPECT_LT(CentreErrorPx(f.scene, fit.posterior.pose, base), 0.1);
}

TEST(DirectAligner, AlignsALowContrastFloor) {
  Fixture f;
  // The gravel photo at 12 % of its contrast and smoothed: a plain, nearly uniform floor whose
  // remaining texture is at the noise level of a single pixel.
  cv::Mat plain;
  cv::GaussianBlur(f.scene.floor, plain, {0, 0}, 1.5);
  plain.convertTo(plain, CV_8U, 0.12, 128 - 0.12 * cv::mean(plain)[0]);
  f.scene.floor = plain;
  mosaic::ImageRasterSource source(plain, f.scene.geo);
  NormalizedMosaic normalized(&source, 7, 16 << 20);
  DirectAligner aligner(SmallCameraOptions(), f.scene.camera, &normalized);
  const Pose2 base = TrueBase();
  const cv::Mat frame = f.scene.Render(base, 1.0, 0.0);
  const PoseWithCovariance prior =
      Prior(f.scene, base, {0.001, 0.001, 0.005}, {0.002, 0.002, 0.01});
  const DirectAlignment fit = aligner.Align(frame, prior, prior.pose);
  ASSERT_TRUE(fit.valid) << fit.reason;
  EXPECT_LT(CentreErrorPx(f.scene, fit.posterior.pose, base), 0.15);
}

// The frame the camera would see at `base` over another floor (a brick photo).
cv::Mat FrameOfAnotherFloor(const Pose2& base) {
  TestScene other;
  other.floor = cv::imread(FLEETLOC_SOURCE_DIR "/tests/data/brick.png", cv::IMREAD_GRAYSCALE);
  EXPECT_FALSE(other.floor.empty());
  return other.Render(base, 1.0, 0.0);
}

TEST(DirectAligner, RefusesAFrameOfAnotherFloor) {
  Fixture f;
  const Pose2 base = TrueBase();
  const cv::Mat frame = FrameOfAnotherFloor(base);
  for (const double sigma_m : {0.002, 0.006}) {
    const PoseWithCovariance prior = Prior(f.scene, base, {0, 0, 0}, {sigma_m, sigma_m, 0.01});
    const DirectAlignment fit = f.aligner.Align(frame, prior, prior.pose);
    EXPECT_FALSE(fit.valid) << "sigma " << sigma_m << ": correlation " << fit.correlation;
    EXPECT_LT(fit.peak_z, 8.0) << "sigma " << sigma_m;
  }
}

// A floor whose coarse content repeats every `period_px` (one period of the gravel photo smoothed
// by 1 px, tiled: tiles, painted grids) under the photo's own finest texture times `fine_gain`,
// which does not repeat. At the search level the repeats look alike.
cv::Mat TiledFloor(const cv::Mat& photo, int period_px, double fine_gain) {
  cv::Mat f, coarse;
  photo.convertTo(f, CV_32F);
  cv::GaussianBlur(f, coarse, {0, 0}, 1.0);
  const cv::Mat fine = f - coarse;
  const cv::Mat tile = coarse(cv::Rect(200, 200, period_px, period_px)).clone();
  cv::Mat floor(f.size(), CV_32F);
  for (int y = 0; y < f.rows; ++y) {
    for (int x = 0; x < f.cols; ++x) {
      floor.at<float>(y, x) =
          tile.at<float>(y % period_px, x % period_px) + fine_gain * fine.at<float>(y, x);
    }
  }
  floor.convertTo(floor, CV_8U);
  return floor;
}

// The search's peaks one period apart are ambiguous; aligning the rival peak as well tells them
// apart where the fine texture differs, and refuses where even the aligned fits look alike.
TEST(DirectAligner, ARepeatedCoarsePatternIsToldApartByAligningTheRivalPeak) {
  for (const double fine_gain : {2.0, 1.0}) {
    TestScene scene;
    scene.floor = TiledFloor(scene.floor, 32, fine_gain);
    mosaic::ImageRasterSource source(scene.floor, scene.geo);
    NormalizedMosaic normalized(&source, 7, 16 << 20);
    const Pose2 base = TrueBase();
    const cv::Mat frame = scene.Render(base, 1.0, 0.0);
    const PoseWithCovariance prior =
        Prior(scene, base, {0.001, -0.001, 0.0}, {0.005, 0.005, 0.005});
    DirectAlignOptions options = SmallCameraOptions();
    for (const bool verify : {false, true}) {
      options.verify_rival_peak = verify;
      const DirectAligner aligner(options, scene.camera, &normalized);
      const DirectAlignment fit = aligner.Align(frame, prior, prior.pose);
      SCOPED_TRACE(testing::Message() << "fine gain " << fine_gain << ", verify " << verify << ": "
                                      << fit.reason << ", peak ratio " << fit.peak_ratio);
      EXPECT_TRUE(fit.searched);
      EXPECT_EQ(fit.valid, verify && fine_gain == 2.0);
      if (fit.valid) {
        EXPECT_LT(CentreErrorPx(scene, fit.posterior.pose, base), 0.1);
      }
    }
  }
}

TEST(DirectAligner, CovarianceCoversTheError) {
  Fixture f;
  cv::RNG rng(11);
  double nees_sum = 0.0;
  const int trials = 20;
  for (int k = 0; k < trials; ++k) {
    const Pose2 base =
        Pose2{0.1 + 0.002 * k, 0.12 + 0.0015 * k, 0.3 * k} * Pose2{0.1, 0, 0}.Inverse();
    cv::Mat frame = f.scene.Render(base, rng.uniform(0.8, 1.2), rng.uniform(-10.0, 10.0));
    Occlude(&frame, 0.1, rng);
    const Eigen::Vector3d error(rng.gaussian(0.001), rng.gaussian(0.001), rng.gaussian(0.005));
    const PoseWithCovariance prior = Prior(f.scene, base, error, {0.001, 0.001, 0.005});
    const DirectAlignment fit = f.aligner.Align(frame, prior, prior.pose);
    ASSERT_TRUE(fit.valid) << "trial " << k << ": " << fit.reason;
    const Pose2 truth = base * f.scene.camera.mount;
    const Eigen::Vector3d d(fit.posterior.pose.x - truth.x, fit.posterior.pose.y - truth.y,
                            geometry::WrapAngle(fit.posterior.pose.theta - truth.theta));
    nees_sum += d.dot(fit.posterior.covariance.inverse() * d);
  }
  // Mean normalized error squared is 3 for an honest 3-dof covariance; allow a factor of 2 for
  // over-confidence and require it not to be grossly pessimistic either.
  const double nees = nees_sum / trials;
  EXPECT_LT(nees, 6.0);
  EXPECT_GT(nees, 0.3);
}

// Sensor noise as a short exposure has it (read noise 4 DN).
cv::Mat Noisy(const cv::Mat& frame, cv::RNG& rng) {
  cv::Mat noise(frame.size(), CV_32F), f;
  rng.fill(noise, cv::RNG::NORMAL, 0.0, 4.0);
  frame.convertTo(f, CV_32F);
  cv::Mat noisy;
  cv::Mat(f + noise).convertTo(noisy, CV_8U);
  return noisy;
}

// Polishes of 12 noisy frames from template-like fits (each axis up to `max_off_m` off, the heading
// up to 5e-4 rad) under a loose odometry prior: the start's and the polish's camera-centre RMS (px)
// and the polish's mean NEES.
struct PolishTrials {
  double start_rms_px = 0.0, polished_rms_px = 0.0, mean_nees = 0.0;
  int wide_windows = 0;  // polishes over a window wider than the mosaic's
  int unsmoothed = 0;    // level-0 polishes without the matching's smoothing
};

// `degrade` turns a rendered frame into the camera's (default: Noisy).
PolishTrials RunPolishTrials(Fixture& f, const DirectAligner& aligner, uint64 seed,
                             double max_off_m, bool confirming = false,
                             cv::Mat (*degrade)(const cv::Mat&, cv::RNG&) = Noisy) {
  cv::RNG rng(seed);
  double start_sq = 0.0, polished_sq = 0.0, nees_sum = 0.0;
  int wide_windows = 0, unsmoothed = 0;
  const int trials = 12;
  for (int k = 0; k < trials; ++k) {
    const Pose2 base =
        Pose2{0.1 + 0.002 * k, 0.12 + 0.0015 * k, 0.4 * k} * Pose2{0.1, 0, 0}.Inverse();
    const cv::Mat frame = degrade(f.scene.Render(base, rng.uniform(0.8, 1.2), 0.0), rng);
    const Pose2 truth = base * f.scene.camera.mount;
    const Pose2 start{truth.x + rng.uniform(-max_off_m, max_off_m),
                      truth.y + rng.uniform(-max_off_m, max_off_m),
                      truth.theta + rng.uniform(-5e-4, 5e-4)};
    const PoseWithCovariance prior = Prior(f.scene, base, {0, 0, 0}, {0.002, 0.002, 0.01});
    const DirectAlignment fit = aligner.Polish(frame, prior, start, {}, confirming);
    EXPECT_TRUE(fit.valid) << "trial " << k << ": " << fit.reason;
    wide_windows += fit.window_px > f.normalized.WindowAt(0);
    unsmoothed += fit.unsmoothed;
    start_sq += std::pow(CentreErrorPx(f.scene, start, base), 2);
    polished_sq += std::pow(CentreErrorPx(f.scene, fit.posterior.pose, base), 2);
    const Eigen::Vector3d d(fit.posterior.pose.x - truth.x, fit.posterior.pose.y - truth.y,
                            geometry::WrapAngle(fit.posterior.pose.theta - truth.theta));
    nees_sum += d.dot(fit.posterior.covariance.inverse() * d);
  }
  return {std::sqrt(start_sq / trials), std::sqrt(polished_sq / trials), nees_sum / trials,
          wide_windows, unsmoothed};
}

TEST(DirectAligner, PolishTakesANearFitOfANoisyFrameCloserWithAnHonestCovariance) {
  Fixture f;
  // A template-like fit: 0.1–0.2 px off.
  const PolishTrials r = RunPolishTrials(f, f.aligner, 5, 1e-4);
  EXPECT_LT(r.polished_rms_px, 0.05);
  EXPECT_LT(r.polished_rms_px * r.polished_rms_px, 0.2 * r.start_rms_px * r.start_rms_px);
  EXPECT_LT(r.mean_nees, 6.0);
}

// Strong read noise (8 DN) over a frame whose contrast falls from full on the right to a fifth on
// the left (uneven light on a plain floor).
cv::Mat NoisyLowContrastLeft(const cv::Mat& frame, cv::RNG& rng) {
  cv::Mat f, noise(frame.size(), CV_32F);
  frame.convertTo(f, CV_32F);
  const double mean = cv::mean(f)[0];
  for (int x = 0; x < f.cols; ++x) {
    const double contrast = 0.2 + 0.8 * x / (f.cols - 1);
    f.col(x) = mean + contrast * (f.col(x) - mean);
  }
  rng.fill(noise, cv::RNG::NORMAL, 0.0, 8.0);
  cv::Mat noisy;
  cv::Mat(f + noise).convertTo(noisy, CV_8U);
  return noisy;
}

// Low-contrast pixels of a noisy frame are mostly noise once normalized: weighed by the noise the
// polish fits (direct.noise_model), they pull less, and the polish lands closer than with equal
// weights, still with an honest covariance.
TEST(DirectAligner, PolishWeighsLowContrastPixelsByTheirNoise) {
  Fixture f;
  DirectAlignOptions equal_weights = SmallCameraOptions();
  equal_weights.noise_model = false;
  const DirectAligner unweighted(equal_weights, f.scene.camera, &f.normalized);
  // Four runs of 12 frames (measured: camera RMS 0.0167 px weighted, 0.0201 equal; per run the
  // ratio 0.72–0.91).
  double weighted_sq = 0.0, equal_sq = 0.0;
  for (const uint64 seed : {13, 17, 21, 29}) {
    const PolishTrials weighted =
        RunPolishTrials(f, f.aligner, seed, 1e-4, false, NoisyLowContrastLeft);
    const PolishTrials equal =
        RunPolishTrials(f, unweighted, seed, 1e-4, false, NoisyLowContrastLeft);
    weighted_sq += weighted.polished_rms_px * weighted.polished_rms_px;
    equal_sq += equal.polished_rms_px * equal.polished_rms_px;
    EXPECT_LT(weighted.mean_nees, 6.0) << "seed " << seed;
  }
  EXPECT_LT(std::sqrt(weighted_sq / 4), 0.92 * std::sqrt(equal_sq / 4))
      << std::sqrt(weighted_sq / 4) << " against " << std::sqrt(equal_sq / 4);
}

// A frame with occluders over a fifth of it, vignetting and uneven light, and 4 DN read noise.
cv::Mat NoisyOccludedShaded(const cv::Mat& frame, cv::RNG& rng) {
  cv::Mat out = frame.clone();
  Occlude(&out, 0.2, rng);
  Shade(&out);
  return Noisy(out, rng);
}

// Above level 0 the polish normalizes over the mosaic's window or a wider one, and takes the wider
// one's fit only when it is clearly the more precise (DirectAlignOptions::polish_wide_window_px).
// On noisy frames of a clean floor the wider window averages the noise over more pixels: it is
// taken on most frames, for a lower error (measured: 8 of 12 frames, camera RMS 0.0069 and 0.0068
// px against 0.0086 and 0.0087 over the local window alone). Under occluders and uneven light the
// local window is kept (none of 12), and the poses are the local window's.
TEST(DirectAligner, AtLevel1ThePolishTakesAWiderWindowOnlyWhereItIsMorePrecise) {
  DirectAlignOptions local_only = PolishAtLevel1Options(TestScene());
  local_only.polish_wide_window_px = 0;
  // Each run on a fresh scene, so that both aligners see the same frames (the scene draws its own
  // noise).
  const auto trials = [](const DirectAlignOptions& options, uint64 seed,
                         cv::Mat (*degrade)(const cv::Mat&, cv::RNG&)) {
    Fixture f;
    const DirectAligner aligner(options, f.scene.camera, &f.normalized);
    return RunPolishTrials(f, aligner, seed, 1e-4, false, degrade);
  };
  const DirectAlignOptions choosing = PolishAtLevel1Options(TestScene());
  for (const uint64 seed : {3, 7}) {
    const PolishTrials noisy = trials(choosing, seed, Noisy);
    const PolishTrials noisy_local = trials(local_only, seed, Noisy);
    EXPECT_GE(noisy.wide_windows, 6) << "seed " << seed;
    EXPECT_LT(noisy.polished_rms_px, 0.9 * noisy_local.polished_rms_px) << "seed " << seed;
    EXPECT_LT(noisy.mean_nees, 6.0) << "seed " << seed;
    const PolishTrials occluded = trials(choosing, seed, NoisyOccludedShaded);
    const PolishTrials occluded_local = trials(local_only, seed, NoisyOccludedShaded);
    EXPECT_LE(occluded.wide_windows, 1) << "seed " << seed;
    EXPECT_LT(occluded.polished_rms_px, 1.05 * occluded_local.polished_rms_px) << "seed " << seed;
  }
}

// At level 0 the mosaic's normalized tiles are smoothed for the template matching; the polish
// also fits without that smoothing and takes that fit when its sigma is below 1.1 times the
// smoothed one's (DirectAlignOptions::polish_unsmoothed_max_sigma_ratio). On noisy frames it is
// taken on about half of them and lands closer (measured: 7 and 6 of 12, camera RMS 0.0062 and
// 0.0042 px against 0.0067 and 0.0049 smoothed); under occluders and uneven light the two fits are
// as close (0.0261 / 0.0263, 0.0193 / 0.0193).
TEST(DirectAligner, AtLevel0ThePolishDropsTheMatchingsSmoothingWhereThatFitsCloser) {
  DirectAlignOptions smoothed_only = SmallCameraOptions();
  smoothed_only.polish_unsmoothed_max_sigma_ratio = 0;
  const auto trials = [](const DirectAlignOptions& options, uint64 seed,
                         cv::Mat (*degrade)(const cv::Mat&, cv::RNG&)) {
    Fixture f(0.7);
    const DirectAligner aligner(options, f.scene.camera, &f.normalized);
    return RunPolishTrials(f, aligner, seed, 1e-4, false, degrade);
  };
  for (const uint64 seed : {3, 7}) {
    for (const auto degrade : {Noisy, NoisyOccludedShaded}) {
      const PolishTrials choosing = trials(SmallCameraOptions(), seed, degrade);
      const PolishTrials smoothed = trials(smoothed_only, seed, degrade);
      const std::string what = (degrade == Noisy ? "noisy, seed " : "occluded, seed ");
      EXPECT_EQ(smoothed.unsmoothed, 0) << what << seed;
      if (degrade == Noisy) {
        EXPECT_GE(choosing.unsmoothed, 4) << what << seed;
        EXPECT_LT(choosing.polished_rms_px, 0.95 * smoothed.polished_rms_px) << what << seed;
      } else {
        EXPECT_LT(choosing.polished_rms_px, 1.05 * smoothed.polished_rms_px) << what << seed;
      }
      EXPECT_LT(choosing.mean_nees, 6.0) << what << seed;
    }
  }
}

// A noisy frame at the true base, a start a fraction of a pixel off and a loose prior: what the
// tracker's polish gets.
struct NearStart {
  cv::Mat frame;
  Pose2 start;
  PoseWithCovariance prior;
};

NearStart NoisyFrameNearStart(Fixture& f) {
  cv::RNG rng(11);
  const Pose2 base = TrueBase();
  const Pose2 truth = base * f.scene.camera.mount;
  return {Noisy(f.scene.Render(base, 1.0, 0.0), rng),
          {truth.x + 6e-5, truth.y - 4e-5, truth.theta + 2e-4},
          Prior(f.scene, base, {0, 0, 0}, {0.002, 0.002, 0.01})};
}

void ExpectSamePose(const DirectAlignment& a, const DirectAlignment& b) {
  EXPECT_DOUBLE_EQ(a.posterior.pose.x, b.posterior.pose.x);
  EXPECT_DOUBLE_EQ(a.posterior.pose.y, b.posterior.pose.y);
  EXPECT_DOUBLE_EQ(a.posterior.pose.theta, b.posterior.pose.theta);
}

// The normalization a level-0 polish chose, given back with its blur and noise, gives the same
// fit; the other one given gives the other normalization.
TEST(DirectAligner, ALevel0PolishGivenItsNormalizationLandsWhereItDid) {
  Fixture f(0.7);
  const auto [frame, start, prior] = NoisyFrameNearStart(f);
  const DirectAlignment chosen = f.aligner.Polish(frame, prior, start);
  ASSERT_TRUE(chosen.valid) << chosen.reason;
  for (const bool unsmoothed : {false, true}) {
    const DirectAlignment given = f.aligner.Polish(
        frame, prior, start, {chosen.view_blur_px, chosen.noise, chosen.window_px, unsmoothed});
    ASSERT_TRUE(given.valid) << given.reason;
    EXPECT_EQ(given.unsmoothed, unsmoothed);
    if (unsmoothed == chosen.unsmoothed) ExpectSamePose(given, chosen);
  }
}

// The window a level-1 polish chose, given back with its blur and noise (as the tracker carries
// them), gives the same fit without trying the other window.
TEST(DirectAligner, APolishGivenTheWindowItChoseLandsWhereItDid) {
  Fixture f;
  const DirectAligner aligner(PolishAtLevel1Options(f.scene), f.scene.camera, &f.normalized);
  const auto [frame, start, prior] = NoisyFrameNearStart(f);
  const DirectAlignment chosen = aligner.Polish(frame, prior, start);
  ASSERT_TRUE(chosen.valid) << chosen.reason;
  for (const int window : {f.normalized.WindowAt(0), DirectAlignOptions().polish_wide_window_px}) {
    const DirectAlignment given =
        aligner.Polish(frame, prior, start, {chosen.view_blur_px, chosen.noise, window});
    ASSERT_TRUE(given.valid) << given.reason;
    EXPECT_EQ(given.window_px, window);
    if (window == chosen.window_px) ExpectSamePose(given, chosen);
  }
}

// The blur and noise a polish estimated, given back (as the tracker carries them over the next
// frames), reproduce that polish; and the noise fitted to another frame of the same camera weighs
// this one's pixels as its own fit does, to a few thousandths of a pixel.
TEST(DirectAligner, APolishGivenTheModelItEstimatedLandsWhereItDid) {
  Fixture f;
  cv::RNG rng(5);
  const Pose2 base = TrueBase();
  const cv::Mat frame = NoisyLowContrastLeft(f.scene.Render(base, 1.0, 0.0), rng);
  const cv::Mat other = NoisyLowContrastLeft(f.scene.Render(base, 1.0, 0.0), rng);
  const Pose2 truth = base * f.scene.camera.mount;
  const Pose2 start{truth.x + 6e-5, truth.y - 4e-5, truth.theta + 2e-4};
  const PoseWithCovariance prior = Prior(f.scene, base, {0, 0, 0}, {0.002, 0.002, 0.01});
  const DirectAlignment fitted = f.aligner.Polish(frame, prior, start);
  ASSERT_TRUE(fitted.valid) << fitted.reason;
  ASSERT_GT(fitted.noise.b, 0.0);  // this frame's low-contrast half is mostly noise
  const DirectAlignment given =
      f.aligner.Polish(frame, prior, start, {fitted.view_blur_px, fitted.noise});
  ASSERT_TRUE(given.valid) << given.reason;
  EXPECT_EQ(given.noise.b, fitted.noise.b);
  EXPECT_EQ(given.view_blur_px, fitted.view_blur_px);
  EXPECT_DOUBLE_EQ(given.posterior.pose.x, fitted.posterior.pose.x);
  EXPECT_DOUBLE_EQ(given.posterior.pose.y, fitted.posterior.pose.y);
  const DirectAlignment from_other = f.aligner.Polish(other, prior, start);
  const DirectAlignment other_noise =
      f.aligner.Polish(frame, prior, start, {fitted.view_blur_px, from_other.noise});
  ASSERT_TRUE(other_noise.valid) << other_noise.reason;
  ASSERT_NE(from_other.noise.b, fitted.noise.b);
  EXPECT_EQ(other_noise.noise.b, from_other.noise.b);  // taken as given, not fitted again
  EXPECT_LT(CentreErrorPx(f.scene, other_noise.posterior.pose, base) -
                CentreErrorPx(f.scene, fitted.posterior.pose, base),
            0.005);
}

// The polish at level 1 (direct.polish_max_level_pixels below the camera's pixels, as on a
// 1280×1024 camera): its steps and covariance are in level-0 pixels (InLevel0Pixels), so it ends
// closer with an honest covariance, both from a template-like fit (one step) and from a fit valid
// only once polished (farther off; confirm_polish_iterations steps).
TEST(DirectAligner, PolishAtLevel1TakesANearFitCloserWithAnHonestCovariance) {
  Fixture f;
  const DirectAlignOptions at_level_1 = PolishAtLevel1Options(f.scene);
  const DirectAligner aligner(at_level_1, f.scene.camera, &f.normalized);
  ASSERT_EQ(aligner.PolishLevel(), 1);
  // Measured: from 0.16 px RMS, 0.008 px and NEES 0.7; confirming from 0.32 px, 0.010 px and NEES
  // 0.8. With the Jacobian's translation columns left per level-1 pixel, NEES 24 and 7.5.
  for (const PolishTrials& r : {RunPolishTrials(f, aligner, 7, 1e-4),
                                RunPolishTrials(f, aligner, 7, 2e-4, /*confirming=*/true)}) {
    EXPECT_LT(r.polished_rms_px, 0.04) << r.start_rms_px;
    EXPECT_LT(r.polished_rms_px * r.polished_rms_px, 0.05 * r.start_rms_px * r.start_rms_px);
    EXPECT_LT(r.mean_nees, 6.0) << r.start_rms_px;
  }
}

// The polish level: the finest with at most direct.polish_max_level_pixels, but never coarser than
// direct.polish_max_level (a 1280×1024 camera polishes at level 1, not at 320×256).
TEST(DirectAligner, PolishLevelStopsAtTheCoarsestAllowed) {
  Fixture f;
  DirectAlignOptions options = PolishAtLevel1Options(f.scene);
  EXPECT_EQ(DirectAligner(options, f.scene.camera, &f.normalized).PolishLevel(), 1);
  options.polish_max_level = 0;
  EXPECT_EQ(DirectAligner(options, f.scene.camera, &f.normalized).PolishLevel(), 0);
}

// From a template-like fit (0.02–0.05 px off), the linearization at the start is final: one render
// of the view, and the same pose as two linearizations give.
TEST(DirectAligner, PolishFromANearFitTakesOnePassToTheSamePose) {
  Fixture f;
  DirectAlignOptions single_pass = SmallCameraOptions();
  single_pass.polish_single_pass_px = 0.1;
  const DirectAligner aligner(single_pass, f.scene.camera, &f.normalized);
  const DirectAligner& reference = f.aligner;  // the default: two passes
  cv::RNG rng(11);
  for (int k = 0; k < 6; ++k) {
    const Pose2 base = Pose2{0.1 + 0.003 * k, 0.12, 0.5 * k} * Pose2{0.1, 0, 0}.Inverse();
    const cv::Mat frame = Noisy(f.scene.Render(base, 1.0, 0.0), rng);
    const Pose2 truth = base * f.scene.camera.mount;
    const double off = rng.uniform(0.02, 0.05) * kRes;
    const Pose2 start{truth.x + off, truth.y - 0.5 * off, truth.theta};
    const PoseWithCovariance prior = Prior(f.scene, base, {0, 0, 0}, {0.002, 0.002, 0.01});
    const DirectAlignment one = aligner.Polish(frame, prior, start);
    const DirectAlignment two = reference.Polish(frame, prior, start);
    ASSERT_TRUE(one.valid) << "trial " << k << ": " << one.reason;
    ASSERT_TRUE(two.valid) << "trial " << k << ": " << two.reason;
    EXPECT_LT(CentreErrorPx(f.scene, one.posterior.pose, base), 0.03) << "trial " << k;
    const double apart = std::hypot(one.posterior.pose.x - two.posterior.pose.x,
                                    one.posterior.pose.y - two.posterior.pose.y) /
                         kRes;
    EXPECT_LT(apart, 0.005) << "trial " << k;
  }
}

TEST(DirectAligner, PolishRefusesAStartItWouldHaveToMoveFar) {
  Fixture f;
  const Pose2 base = TrueBase();
  const cv::Mat frame = f.scene.Render(base, 1.0, 0.0);
  const Pose2 truth = base * f.scene.camera.mount;
  const PoseWithCovariance prior = Prior(f.scene, base, {0, 0, 0}, {0.002, 0.002, 0.01});
  // 2 px off: a template fit that far is wrong, and the polish must not be the one to say so.
  const DirectAlignment fit =
      f.aligner.Polish(frame, prior, {truth.x + 0.001, truth.y, truth.theta});
  EXPECT_FALSE(fit.valid) << "ended at x " << (fit.posterior.pose.x - truth.x) / 0.0005 << " px, y "
                          << (fit.posterior.pose.y - truth.y) / 0.0005 << " px";
}

TEST(DirectAligner, PolishRefusesAFrameOfAnotherFloor) {
  Fixture f;
  const Pose2 base = TrueBase();
  const PoseWithCovariance prior = Prior(f.scene, base, {0, 0, 0}, {0.002, 0.002, 0.01});
  const DirectAlignment fit = f.aligner.Polish(FrameOfAnotherFloor(base), prior, prior.pose);
  EXPECT_FALSE(fit.valid) << "correlation " << fit.correlation;
}

// Camera-centre RMS (px) of polishes of frames whose grid runs parallel to the mosaic's (headings
// 0 and 90°), at 16 sub-pixel positions, each started 0.07 px off.
double ParallelGridPolishRmsPx(Fixture& f, const DirectAligner& aligner) {
  double sq = 0.0;
  int n = 0;
  for (const double theta : {0.0, M_PI / 2}) {
    cv::RNG rng(3);
    for (int k = 0; k < 16; ++k) {
      const Pose2 base =
          Pose2{0.1 + kRes * 0.37 * k, 0.12 + kRes * 0.61 * k, theta} * Pose2{0.1, 0, 0}.Inverse();
      const cv::Mat frame = Noisy(f.scene.Render(base, 1.0, 0.0), rng);
      const Pose2 truth = base * f.scene.camera.mount;
      const PoseWithCovariance prior = Prior(f.scene, base, {0, 0, 0}, {0.002, 0.002, 0.01});
      const DirectAlignment fit =
          aligner.Polish(frame, prior, {truth.x + 3e-5, truth.y - 2e-5, truth.theta});
      EXPECT_TRUE(fit.valid) << "heading " << theta << ", position " << k << ": " << fit.reason;
      sq += std::pow(CentreErrorPx(f.scene, fit.posterior.pose, base), 2);
      ++n;
    }
  }
  return std::sqrt(sq / n);
}

// A vehicle driving along the mosaic's axes: the level-1 polish must not be pulled towards the
// mosaic's level-1 pixels. Its view is rendered at level 0 and averaged down as the frame is;
// measured 0.045 px RMS at level 1, 0.046 at level 0; rendered from the mosaic's own level 1,
// 0.081 at level 1.
TEST(DirectAligner, PolishAtLevel1OfAFrameParallelToTheMosaicGridIsAsCloseAsAtLevel0) {
  Fixture f;
  const DirectAlignOptions at_level_1 = PolishAtLevel1Options(f.scene);
  const DirectAligner level_1(at_level_1, f.scene.camera, &f.normalized);
  ASSERT_EQ(level_1.PolishLevel(), 1);
  const double at_0 = ParallelGridPolishRmsPx(f, f.aligner);
  const double at_1 = ParallelGridPolishRmsPx(f, level_1);
  EXPECT_LT(at_1, 0.06);
  EXPECT_LT(at_1, 1.25 * at_0) << "level 0: " << at_0;
}

}  // namespace
}  // namespace fleetloc::tracking
