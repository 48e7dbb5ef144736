// The residual noise fit on a real photograph (tests/data/gravel.png) whose contrast falls from
// full on the right to a sixth on the left: under strong sensor noise the low-contrast pixels'
// normalized residuals are noisier, by what the fit predicts; with bright occluders and little
// noise every pixel keeps weight 1.
#include "tracking/noise_precision.h"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "imaging/fast_patch.h"
#include "tracking/normalized_mosaic.h"

namespace fleetloc::tracking {
namespace {

constexpr int kWindow = 7;
constexpr float kEpsilon = NormalizedMosaic::kSpreadEpsilon;

struct Scene {
  cv::Mat photo;  // grey levels as floats
  cv::Rect inner{40, 40, 360, 240};

  Scene() {
    cv::imread(FLEETLOC_SOURCE_DIR "/tests/data/gravel.png", cv::IMREAD_GRAYSCALE)
        .convertTo(photo, CV_32F);
  }
  // The normalized photo over `inner` grown by one pixel (the view).
  cv::Mat View() const {
    const cv::Rect grown(inner.x - 1, inner.y - 1, inner.width + 2, inner.height + 2);
    const cv::Rect padded(grown.x - kWindow, grown.y - kWindow, grown.width + 2 * kWindow,
                          grown.height + 2 * kWindow);
    return imaging::NormalizePatch(photo(padded), kWindow,
                                   kEpsilon)(cv::Rect(kWindow, kWindow, grown.width, grown.height))
        .clone();
  }
  // The photo with its contrast about its mean scaled from 1/6 (the left edge) to 1 (the right),
  // plus Gaussian noise of `noise_dn`.
  cv::Mat Frame(double noise_dn, cv::RNG& rng) const {
    constexpr double left = 1.0 / 6.0;
    const double mean = cv::mean(photo)[0];
    cv::Mat frame(photo.size(), CV_32F);
    for (int y = 0; y < photo.rows; ++y) {
      for (int x = 0; x < photo.cols; ++x) {
        const double contrast = left + (1.0 - left) * x / (photo.cols - 1);
        frame.at<float>(y, x) =
            static_cast<float>(mean + contrast * (photo.at<float>(y, x) - mean));
      }
    }
    cv::Mat noise(frame.size(), CV_32F);
    rng.fill(noise, cv::RNG::NORMAL, 0.0, noise_dn);
    return frame + noise;
  }
};

struct Fitted {
  cv::Mat normalized, variance;
  // u at a pixel of the frame.
  float U(int y, int x) const {
    return NormalizationFactorSquared(variance.at<float>(y, x), kEpsilon);
  }
  ResidualNoise noise;
};

Fitted Fit(const Scene& scene, const cv::Mat& frame) {
  Fitted f;
  f.normalized = imaging::NormalizePatch(frame, kWindow, kEpsilon, &f.variance);
  f.noise = FitResidualNoise(f.normalized, scene.View(), scene.inner, {}, f.variance, kEpsilon);
  return f;
}

// The mean squared residual t − gain·v over columns [x0, x1) of `inner`, and the mean u there.
std::pair<double, double> StripVariance(const Scene& scene, const Fitted& f, int x0, int x1) {
  const cv::Mat view = scene.View();
  double stv = 0, svv = 0;
  for (int y = 0; y < scene.inner.height; ++y) {
    for (int x = 0; x < scene.inner.width; ++x) {
      const float t = f.normalized.at<float>(scene.inner.y + y, scene.inner.x + x);
      const float v = view.at<float>(y + 1, x + 1);
      stv += t * v;
      svv += v * v;
    }
  }
  const double gain = stv / svv;
  double r2 = 0, u = 0;
  int n = 0;
  for (int y = 0; y < scene.inner.height; ++y) {
    for (int x = x0; x < x1; ++x) {
      const double r = f.normalized.at<float>(scene.inner.y + y, scene.inner.x + x) -
                       gain * view.at<float>(y + 1, x + 1);
      r2 += r * r;
      u += f.U(scene.inner.y + y, scene.inner.x + x);
      ++n;
    }
  }
  return {r2 / n, u / n};
}

TEST(NoisePrecision, FitsTheNoiseOfLowContrastPixels) {
  const Scene scene;
  ASSERT_FALSE(scene.photo.empty());
  cv::RNG rng(3);
  const Fitted f = Fit(scene, scene.Frame(6.0, rng));
  ASSERT_GT(f.noise.b, 0.0);
  // The fitted variance against the measured one, in the low-contrast and high-contrast strips.
  const auto [low_r2, low_u] = StripVariance(scene, f, 0, 60);
  const auto [high_r2, high_u] = StripVariance(scene, f, 300, 360);
  EXPECT_GT(low_r2, 3.0 * high_r2);
  EXPECT_NEAR((f.noise.a + f.noise.b * low_u) / (f.noise.a + f.noise.b * high_u), low_r2 / high_r2,
              0.3 * low_r2 / high_r2);
  // The weights follow: a low-contrast pixel counts less than a high-contrast one.
  const cv::Mat precision = ResidualPrecision(f.noise, f.variance, kEpsilon);
  ASSERT_FALSE(precision.empty());
  EXPECT_NEAR(precision.at<float>(scene.inner.y + 100, scene.inner.x + 30),
              f.noise.Precision(f.U(scene.inner.y + 100, scene.inner.x + 30)), 1e-4);
  EXPECT_LT(cv::mean(precision(cv::Rect(scene.inner.x, scene.inner.y, 60, 240)))[0],
            0.5 * cv::mean(precision(cv::Rect(scene.inner.x + 300, scene.inner.y, 60, 240)))[0]);
}

TEST(NoisePrecision, BrightOccludersDoNotLowerTheOtherPixelsWeights) {
  const Scene scene;
  cv::RNG rng(7);
  cv::Mat frame = scene.Frame(0.5, rng);
  for (int k = 0; k < 40; ++k) {
    const cv::Point c(rng.uniform(scene.inner.x, scene.inner.br().x),
                      rng.uniform(scene.inner.y, scene.inner.br().y));
    cv::circle(frame, c, rng.uniform(4, 12), cv::Scalar(rng.uniform(0, 2) ? 250 : 5), cv::FILLED);
  }
  const Fitted f = Fit(scene, frame);
  EXPECT_EQ(f.noise.b, 0.0);
  EXPECT_TRUE(ResidualPrecision(f.noise, f.variance, kEpsilon).empty());
}

}  // namespace
}  // namespace fleetloc::tracking
