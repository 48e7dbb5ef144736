// Tests for the camera renderer: geometry against the geotransform and camera model, sub-pixel
// shifts, photometric effects and determinism.
#include "sim/camera_renderer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "sim/sim_test_util.h"

namespace fleetloc::sim {
namespace {

using testing::kResolutionM;
using testing::SmallCamera;

cv::Mat Gravel() {
  cv::Mat image = cv::imread(FLEETLOC_SOURCE_DIR "/tests/data/gravel.png", cv::IMREAD_GRAYSCALE);
  EXPECT_FALSE(image.empty());
  return image;
}

// The gravel image as a floor with its top-left corner at map (1, 2).
mosaic::ImageRasterSource GravelFloor() {
  return mosaic::ImageRasterSource(Gravel(), geometry::Geotransform{1.0, 2.0, kResolutionM});
}

// base_link pose that puts the camera's principal point on mosaic pixel (u, v), heading theta.
geometry::Pose2 BaseSeeing(const geometry::CameraModel& camera, double u, double v, double theta) {
  const geometry::Geotransform geo{1.0, 2.0, kResolutionM};
  const Eigen::Vector2d xy = geo.PixelToMap({u, v});
  return geometry::Pose2{xy.x(), xy.y(), theta} * camera.mount.Inverse();
}

// Bilinear sample of an 8-bit image at continuous coordinates (pixel centres at i + 0.5).
double Bilinear(const cv::Mat& image, const Eigen::Vector2d& uv) {
  const double x = uv.x() - 0.5, y = uv.y() - 0.5;
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  const double fx = x - x0, fy = y - y0;
  auto at = [&](int i, int j) { return static_cast<double>(image.at<std::uint8_t>(j, i)); };
  return (1 - fy) * ((1 - fx) * at(x0, y0) + fx * at(x0 + 1, y0)) +
         fy * ((1 - fx) * at(x0, y0 + 1) + fx * at(x0 + 1, y0 + 1));
}

RenderOptions Clean(int supersample) {
  RenderOptions options = CleanRenderOptions(RenderOptions{});
  options.supersample = supersample;
  return options;
}

TEST(CameraRenderer, PixelEqualsBilinearSourceAtPredictedMosaicPosition) {
  const cv::Mat gravel = Gravel();
  mosaic::ImageRasterSource floor = GravelFloor();
  const geometry::CameraModel camera = SmallCamera();
  CameraRenderer renderer(&floor, camera, Clean(1), 7);
  const geometry::Pose2 base = BaseSeeing(camera, 251.37, 263.81, 0.7);
  const cv::Mat image = renderer.Render(base, {0, 0}, 0).image;
  double sum_abs = 0.0, max_abs = 0.0;
  for (int j = 0; j < camera.height_px; ++j) {
    for (int i = 0; i < camera.width_px; ++i) {
      const Eigen::Vector2d mosaic = renderer.ImageToMosaic(base, {i + 0.5, j + 0.5});
      const double error = image.at<std::uint8_t>(j, i) - Bilinear(gravel, mosaic);
      sum_abs += std::abs(error);
      max_abs = std::max(max_abs, std::abs(error));
    }
  }
  // Rounding to 8 bits (≤ 0.5) plus OpenCV's 1/32-pixel interpolation grid.
  EXPECT_LT(sum_abs / camera.width_px / camera.height_px, 0.6);
  EXPECT_LT(max_abs, 4.0);
}

TEST(CameraRenderer, ImageToMosaicFollowsCameraModelMountAndGeotransform) {
  mosaic::ImageRasterSource floor = GravelFloor();
  const geometry::CameraModel camera = SmallCamera();
  CameraRenderer renderer(&floor, camera, Clean(1), 7);
  // Heading 0: image up (-v) is map +x, image left (-u) is map +y, i.e. mosaic -v.
  const geometry::Pose2 base = BaseSeeing(camera, 200.0, 300.0, 0.0);
  const Eigen::Vector2d centre = renderer.ImageToMosaic(base, {64.0, 48.0});
  EXPECT_NEAR(centre.x(), 200.0, 1e-9);
  EXPECT_NEAR(centre.y(), 300.0, 1e-9);
  const Eigen::Vector2d up = renderer.ImageToMosaic(base, {64.0, 38.0});  // 10 px up the image
  EXPECT_NEAR(up.x(), 210.0, 1e-9);
  EXPECT_NEAR(up.y(), 300.0, 1e-9);
  const Eigen::Vector2d left = renderer.ImageToMosaic(base, {54.0, 48.0});  // 10 px left
  EXPECT_NEAR(left.x(), 200.0, 1e-9);
  EXPECT_NEAR(left.y(), 290.0, 1e-9);
}

TEST(CameraRenderer, SupersampledPixelIsTheAreaAverageOfTheFloor) {
  const cv::Mat gravel = Gravel();
  mosaic::ImageRasterSource floor = GravelFloor();
  const geometry::CameraModel camera = SmallCamera();
  CameraRenderer renderer(&floor, camera, Clean(3), 7);
  const geometry::Pose2 base = BaseSeeing(camera, 260.2, 240.9, -2.1);
  const cv::Mat image = renderer.Render(base, {0, 0}, 0).image;
  double sum_abs = 0.0;
  for (int j = 0; j < camera.height_px; ++j) {
    for (int i = 0; i < camera.width_px; ++i) {
      double mean = 0.0;  // the 3×3 sub-pixel samples the sensor integrates
      for (int b = 0; b < 3; ++b) {
        for (int a = 0; a < 3; ++a) {
          mean += Bilinear(
              gravel, renderer.ImageToMosaic(base, {i + (a + 0.5) / 3.0, j + (b + 0.5) / 3.0}));
        }
      }
      sum_abs += std::abs(image.at<std::uint8_t>(j, i) - mean / 9.0);
    }
  }
  EXPECT_LT(sum_abs / camera.width_px / camera.height_px, 0.6);
}

// The translation d with b(x) = a(x - d): the peak of the phase-only correlation surface (Hann
// window; frequencies up to half the band, where the floor's texture dominates interpolation and
// rounding noise), located by evaluating the inverse DFT directly on ever finer grids around the
// whole-pixel peak.
cv::Point2d Shift(const cv::Mat& a, const cv::Mat& b) {
  cv::Mat fa, fb, window, spectrum_a, spectrum_b;
  a.convertTo(fa, CV_64F);
  b.convertTo(fb, CV_64F);
  cv::createHanningWindow(window, a.size(), CV_64F);
  cv::dft(fa.mul(window), spectrum_a, cv::DFT_COMPLEX_OUTPUT);
  cv::dft(fb.mul(window), spectrum_b, cv::DFT_COMPLEX_OUTPUT);
  std::vector<double> fx, fy;  // kept frequencies, radians per pixel
  for (int i = 0; i < a.cols; ++i) {
    const double f = 2.0 * M_PI * (i <= a.cols / 2 ? i : i - a.cols) / a.cols;
    if (std::abs(f) < M_PI / 2) fx.push_back(f);
  }
  for (int j = 0; j < a.rows; ++j) {
    const double f = 2.0 * M_PI * (j <= a.rows / 2 ? j : j - a.rows) / a.rows;
    if (std::abs(f) < M_PI / 2) fy.push_back(f);
  }
  // z(j, i) = normalized conj(A) · B at the kept frequencies; surface(d) = Re Σ z e^{i f·d}.
  Eigen::MatrixXcd z(fy.size(), fx.size());
  auto index = [](double f, int n) {
    return static_cast<int>(std::lround(f * n / (2.0 * M_PI) + n)) % n;
  };
  for (size_t j = 0; j < fy.size(); ++j) {
    for (size_t i = 0; i < fx.size(); ++i) {
      const auto& za = spectrum_a.at<cv::Vec2d>(index(fy[j], a.rows), index(fx[i], a.cols));
      const auto& zb = spectrum_b.at<cv::Vec2d>(index(fy[j], a.rows), index(fx[i], a.cols));
      const std::complex<double> cross =
          std::conj(std::complex<double>(za[0], za[1])) * std::complex<double>(zb[0], zb[1]);
      z(j, i) = std::abs(cross) > 0 ? cross / std::abs(cross) : 0.0;
    }
  }
  const cv::Point2d coarse = cv::phaseCorrelate(fa, fb, window);
  Eigen::Vector2d best(std::round(coarse.x), std::round(coarse.y));
  constexpr int kHalf = 10;
  for (const double step : {0.1, 0.01, 0.001}) {
    Eigen::MatrixXcd px(fx.size(), 2 * kHalf + 1), py(2 * kHalf + 1, fy.size());
    for (int k = -kHalf; k <= kHalf; ++k) {
      for (size_t i = 0; i < fx.size(); ++i)
        px(i, k + kHalf) = std::polar(1.0, fx[i] * (best.x() + k * step));
      for (size_t j = 0; j < fy.size(); ++j)
        py(k + kHalf, j) = std::polar(1.0, fy[j] * (best.y() + k * step));
    }
    const Eigen::MatrixXd surface = (py * z * px).real();  // rows: dy steps, cols: dx steps
    Eigen::Index row, col;
    surface.maxCoeff(&row, &col);
    best += step * Eigen::Vector2d(col - kHalf, row - kHalf);
  }
  return {best.x(), best.y()};
}

TEST(CameraRenderer, SubPixelCameraShiftIsRecoveredByPhaseCorrelation) {
  mosaic::ImageRasterSource floor = GravelFloor();
  geometry::CameraModel camera = SmallCamera();  // 256×192: more texture for the estimator
  camera.width_px = 256;
  camera.height_px = 192;
  camera.cx_px = 128.0;
  camera.cy_px = 96.0;
  RenderOptions options = Clean(3);
  options.blur_sigma_px = 0.7;
  CameraRenderer renderer(&floor, camera, options, 7);
  const geometry::Pose2 base = BaseSeeing(camera, 256.0, 256.0, 0.4);
  const cv::Mat reference = renderer.Render(base, {0, 0}, 0).image;
  for (const cv::Point2d image_shift : {cv::Point2d(0.3, -0.45), cv::Point2d(-1.25, 0.6),
                                        cv::Point2d(0.5, 0.5), cv::Point2d(2.85, -0.1)}) {
    // Move the camera (mount yaw 0) onto the floor point that pixel pp + d saw: the floor moves
    // by -d across the image.
    const Eigen::Vector2d ground =
        camera.PixelToGround({camera.cx_px + image_shift.x, camera.cy_px + image_shift.y});
    const geometry::Pose2 moved = base * geometry::Pose2{ground.x(), ground.y(), 0.0};
    const cv::Mat shifted = renderer.Render(moved, {0, 0}, 0).image;
    const cv::Point2d found = Shift(shifted, reference);
    EXPECT_NEAR(found.x, image_shift.x, 0.02) << image_shift;
    EXPECT_NEAR(found.y, image_shift.y, 0.02) << image_shift;
  }
}

TEST(CameraRenderer, GainAndBiasAreAppliedPerFrame) {
  mosaic::ImageRasterSource floor = GravelFloor();
  const geometry::CameraModel camera = SmallCamera();
  RenderOptions options = Clean(3);
  options.gain_min = 0.7;
  options.gain_max = 1.3;
  options.bias_min_dn = -20.0;
  options.bias_max_dn = 20.0;
  CameraRenderer clean(&floor, camera, Clean(3), 7);
  CameraRenderer renderer(&floor, camera, options, 7);
  const geometry::Pose2 base = BaseSeeing(camera, 256.0, 256.0, 0.3);
  const cv::Mat reference = clean.Render(base, {0, 0}, 0).image;
  for (int frame = 0; frame < 3; ++frame) {
    const RenderedFrame rendered = renderer.Render(base, {0, 0}, frame);
    EXPECT_GE(rendered.gain, 0.7);
    EXPECT_LE(rendered.gain, 1.3);
    double sum_abs = 0.0;
    int counted = 0;
    for (int j = 0; j < camera.height_px; ++j) {
      for (int i = 0; i < camera.width_px; ++i) {
        const double predicted =
            reference.at<std::uint8_t>(j, i) * rendered.gain + rendered.bias_dn;
        if (predicted < 1 || predicted > 254) continue;  // saturated
        sum_abs += std::abs(rendered.image.at<std::uint8_t>(j, i) - predicted);
        ++counted;
      }
    }
    // The clean frame was rounded once already: at most 0.5 · gain + 0.5 apart.
    EXPECT_LT(sum_abs / counted, 0.5);
  }
}

TEST(CameraRenderer, DustCoversTheConfiguredFractionOnAverage) {
  mosaic::ImageRasterSource floor = GravelFloor();
  const geometry::CameraModel camera = SmallCamera();
  RenderOptions options = Clean(3);
  options.dust_fraction = 0.08;
  CameraRenderer renderer(&floor, camera, options, 11);
  double coverage_sum = 0.0;
  int frames = 0;
  for (double u = 100; u <= 412; u += 52) {
    for (double v = 100; v <= 412; v += 52) {
      coverage_sum += renderer.Render(BaseSeeing(camera, u, v, 0.01 * u), {0, 0}, 0).dust_coverage;
      ++frames;
    }
  }
  EXPECT_NEAR(coverage_sum / frames, 0.08, 0.025);
}

TEST(CameraRenderer, DustStaysOnTheFloorBetweenVisits) {
  mosaic::ImageRasterSource floor = GravelFloor();
  const geometry::CameraModel camera = SmallCamera();
  RenderOptions options = Clean(3);
  options.dust_fraction = 0.3;
  CameraRenderer renderer(&floor, camera, options, 11);
  const geometry::Pose2 base = BaseSeeing(camera, 256.0, 256.0, 0.5);
  // Different frame indices (other per-frame draws) at one pose: the same dirt.
  EXPECT_EQ(cv::norm(renderer.Render(base, {0, 0}, 1).image, renderer.Render(base, {0, 0}, 2).image,
                     cv::NORM_INF),
            0.0);
}

TEST(CameraRenderer, VignettingDarkensCornersByTheConfiguredLoss) {
  mosaic::ImageRasterSource flat(cv::Mat(512, 512, CV_8UC1, cv::Scalar(200)),
                                 geometry::Geotransform{1.0, 2.0, kResolutionM});
  const geometry::CameraModel camera = SmallCamera();
  RenderOptions options = Clean(3);
  options.vignetting_corner_loss = 0.25;
  CameraRenderer renderer(&flat, camera, options, 3);
  const cv::Mat image = renderer.Render(BaseSeeing(camera, 256, 256, 0), {0, 0}, 0).image;
  EXPECT_NEAR(image.at<std::uint8_t>(48, 64), 200.0, 1.0);
  EXPECT_NEAR(image.at<std::uint8_t>(0, 0), 150.0, 2.0);  // corner pixel centre is 0.5 px inside
  EXPECT_NEAR(image.at<std::uint8_t>(95, 127), 150.0, 2.0);
}

TEST(CameraRenderer, DefaultEffectsChangeTheImageButKeepItsStructure) {
  mosaic::ImageRasterSource floor = GravelFloor();
  const geometry::CameraModel camera = SmallCamera();
  CameraRenderer clean(&floor, camera, Clean(3), 5);
  CameraRenderer real(&floor, camera, RenderOptions{}, 5);
  const geometry::Pose2 base = BaseSeeing(camera, 256.0, 256.0, 1.0);
  const cv::Mat a = clean.Render(base, {0, 0}, 0).image;
  const cv::Mat b = real.Render(base, {0, 0}, 0).image;
  cv::Mat fa, fb, correlation;
  a.convertTo(fa, CV_32F);
  b.convertTo(fb, CV_32F);
  EXPECT_GT(cv::norm(fa, fb, cv::NORM_L1) / fa.total(), 3.0);  // visibly different pixels
  cv::matchTemplate(fa, fb, correlation, cv::TM_CCOEFF_NORMED);
  EXPECT_GT(correlation.at<float>(0, 0), 0.5);  // but still the same floor
  EXPECT_LT(correlation.at<float>(0, 0), 0.98);
}

TEST(CameraRenderer, ExposureBlursAlongTheImageVelocity) {
  mosaic::ImageRasterSource floor = GravelFloor();
  const geometry::CameraModel camera = SmallCamera();
  RenderOptions options = Clean(3);
  CameraRenderer sharp(&floor, camera, options, 1);
  options.exposure_s = 0.01;
  CameraRenderer blurred(&floor, camera, options, 1);
  const geometry::Pose2 base = BaseSeeing(camera, 256.0, 256.0, 0.2);
  // The floor sweeps 10 px along +v during the exposure.
  const Eigen::Vector2d velocity_px_s(0.0, 1000.0);
  cv::Mat a, b;
  sharp.Render(base, velocity_px_s, 0).image.convertTo(a, CV_32F);
  blurred.Render(base, velocity_px_s, 0).image.convertTo(b, CV_32F);
  auto energy = [](const cv::Mat& image, int dx, int dy) {
    cv::Mat gradient;
    cv::Sobel(image, gradient, CV_32F, dx, dy);
    return cv::norm(gradient);
  };
  EXPECT_LT(energy(b, 0, 1) / energy(a, 0, 1), 0.5);  // along v: smeared
  EXPECT_GT(energy(b, 1, 0) / energy(a, 1, 0), 0.6);  // along u: mostly kept
}

TEST(CameraRenderer, SameSeedGivesIdenticalFramesOtherSeedsDiffer) {
  mosaic::ImageRasterSource floor = GravelFloor();
  const geometry::CameraModel camera = SmallCamera();
  CameraRenderer a(&floor, camera, RenderOptions{}, 42), b(&floor, camera, RenderOptions{}, 42);
  CameraRenderer c(&floor, camera, RenderOptions{}, 43);
  const geometry::Pose2 base = BaseSeeing(camera, 256.0, 256.0, 1.0);
  const cv::Mat first = a.Render(base, {300, 0}, 4).image;
  EXPECT_EQ(cv::norm(first, b.Render(base, {300, 0}, 4).image, cv::NORM_INF), 0.0);
  EXPECT_GT(cv::norm(first, c.Render(base, {300, 0}, 4).image, cv::NORM_INF), 0.0);
  EXPECT_GT(cv::norm(first, a.Render(base, {300, 0}, 5).image, cv::NORM_INF), 0.0);
}

TEST(CameraRenderer, FrameHangingOffTheFloorShowsMirroredFloorNotBlack) {
  mosaic::ImageRasterSource floor = GravelFloor();
  const geometry::CameraModel camera = SmallCamera();
  CameraRenderer renderer(&floor, camera, Clean(3), 1);
  // Principal point 20 px inside the left edge: the left 44 columns see beyond the floor.
  const cv::Mat image = renderer.Render(BaseSeeing(camera, 20.0, 256.0, M_PI / 2), {0, 0}, 0).image;
  cv::Scalar mean, stddev;
  cv::meanStdDev(image, mean, stddev);
  EXPECT_GT(stddev[0], 10.0);
  EXPECT_EQ(cv::countNonZero(image == 0), 0);
}

}  // namespace
}  // namespace fleetloc::sim
