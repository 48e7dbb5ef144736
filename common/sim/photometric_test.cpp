// Tests for the photometric effects: blur kernels, light and vignetting fields, sensor response,
// JPEG compression.
#include "sim/photometric.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <string>

#include "sim/sim_options.h"

namespace fleetloc::sim {
namespace {

TEST(MotionBlurKernel, IsAUniformCentredLineOfTheDisplacementLength) {
  const Eigen::Vector2d displacement(6.0, -2.5);  // 6.5 px
  const cv::Mat kernel = MotionBlurKernel(displacement);
  EXPECT_NEAR(cv::sum(kernel)[0], 1.0, 1e-6);
  const Eigen::Vector2d centre((kernel.cols - 1) / 2.0, (kernel.rows - 1) / 2.0);
  const Eigen::Vector2d along = displacement.normalized();
  double mean_along = 0.0, var_along = 0.0, var_across = 0.0;
  for (int v = 0; v < kernel.rows; ++v) {
    for (int u = 0; u < kernel.cols; ++u) {
      const Eigen::Vector2d p = Eigen::Vector2d(u, v) - centre;
      const double w = kernel.at<float>(v, u);
      mean_along += w * p.dot(along);
      var_along += w * std::pow(p.dot(along), 2);
      var_across += w * std::pow(p.x() * along.y() - p.y() * along.x(), 2);
    }
  }
  EXPECT_NEAR(mean_along, 0.0, 1e-3);
  // A uniform segment of length L has variance L²/12; bilinear splatting adds up to 1/4 px².
  EXPECT_NEAR(var_along, 6.5 * 6.5 / 12.0 + 0.15, 0.15);
  EXPECT_LT(var_across, 0.2);
  EXPECT_EQ(MotionBlurKernel({0.01, 0.0}).total(), 1u);  // negligible motion: identity
}

TEST(ApplyBlur, MotionBlurSmearsAlongTheMotionOnly) {
  cv::Mat image(64, 64, CV_32FC1);
  cv::RNG rng(3);
  rng.fill(image, cv::RNG::UNIFORM, 0.0, 255.0);
  cv::Mat blurred = image.clone();
  ApplyBlur(0.0, {8.0, 0.0}, &blurred);
  cv::Mat gx, gy, bx, by;
  cv::Sobel(image, gx, CV_32F, 1, 0);
  cv::Sobel(image, gy, CV_32F, 0, 1);
  cv::Sobel(blurred, bx, CV_32F, 1, 0);
  cv::Sobel(blurred, by, CV_32F, 0, 1);
  EXPECT_LT(cv::norm(bx) / cv::norm(gx), 0.3);  // along the motion: strongly smoothed
  EXPECT_GT(cv::norm(by) / cv::norm(gy), 0.3);  // across: only averaged over 8 px rows
  EXPECT_GT(cv::norm(by) / cv::norm(bx), 2.0);
}

TEST(LightingField, IsSmoothAndWithinTheAmplitude) {
  cv::RNG rng(9);
  const cv::Mat field = LightingField({640, 480}, 0.15, rng);
  double lo = 0.0, hi = 0.0;
  cv::minMaxLoc(field, &lo, &hi);
  EXPECT_GE(lo, 0.85 - 1e-6);
  EXPECT_LE(hi, 1.15 + 1e-6);
  EXPECT_GT(hi - lo, 0.05);  // it does vary
  cv::Mat gx;
  cv::Sobel(field, gx, CV_32F, 1, 0, 1);
  double max_step = 0.0;
  cv::minMaxLoc(cv::abs(gx), nullptr, &max_step);
  EXPECT_LT(max_step, 0.01);  // under 0.5 % change per pixel: low frequency only
  EXPECT_TRUE(LightingField({64, 48}, 0.0, rng).empty());
}

TEST(VignettingField, FallsOffAsCosineToTheFourth) {
  geometry::CameraModel camera;  // 640×480, principal point at the centre
  const cv::Mat field = VignettingField(camera, 0.3);
  EXPECT_NEAR(field.at<float>(240, 320), 1.0, 1e-3);
  EXPECT_NEAR(field.at<float>(0, 0), 0.7, 2e-3);  // pixel centre 0.7 px inside the corner
  // Halfway to the corner: cos^4(atan(r / f)) with the same focal length.
  const double corner_r = std::hypot(320.0, 240.0);
  const double f = corner_r / std::sqrt(1.0 / std::sqrt(0.7) - 1.0);
  const double r = std::hypot(160.5 - 320.0, 120.5 - 240.0);
  EXPECT_NEAR(field.at<float>(120, 160), std::pow(std::cos(std::atan(r / f)), 4), 1e-4);
}

TEST(ApplySensor, ResponseCurveIsMonotonicAndFixesBlackAndWhite) {
  cv::Mat ramp(1, 256, CV_32FC1);
  for (int i = 0; i < 256; ++i) ramp.at<float>(0, i) = static_cast<float>(i);
  RenderOptions options = CleanRenderOptions(RenderOptions{});
  options.response_gamma = 0.8;
  options.response_s_curve = 0.3;
  cv::RNG rng(1);
  const cv::Mat out = ApplySensor(ramp, {}, {1.0, 0.0}, options, rng);
  EXPECT_EQ(out.at<std::uint8_t>(0, 0), 0);
  EXPECT_EQ(out.at<std::uint8_t>(0, 255), 255);
  for (int i = 1; i < 256; ++i)
    EXPECT_GE(out.at<std::uint8_t>(0, i), out.at<std::uint8_t>(0, i - 1));
  cv::Mat out_dn;
  out.convertTo(out_dn, CV_32F);
  EXPECT_GT(cv::norm(out_dn, ramp, cv::NORM_INF), 10.0);  // not the identity
}

TEST(ApplySensor, NoiseHasTheConfiguredReadAndShotVariance) {
  const cv::Mat dark(200, 200, CV_32FC1, cv::Scalar(20.0)),
      bright(200, 200, CV_32FC1, cv::Scalar(200.0));
  RenderOptions options = CleanRenderOptions(RenderOptions{});
  options.noise_sigma_dn = 2.0;
  options.shot_noise_dn = 0.1;
  cv::RNG rng(4);
  cv::Scalar mean, stddev;
  for (const auto& [level, image] : {std::pair{20.0, dark}, std::pair{200.0, bright}}) {
    cv::meanStdDev(ApplySensor(image, {}, {1.0, 0.0}, options, rng), mean, stddev);
    EXPECT_NEAR(mean[0], level, 0.1);
    // Variance 4 + 0.1 · level, plus 1/12 from rounding to whole grey levels.
    EXPECT_NEAR(stddev[0], std::sqrt(4.0 + 0.1 * level + 1.0 / 12.0), 0.1) << level;
  }
}

// A textured 8-bit frame: noise blurred to a grain of a few pixels, about 40 DN of contrast.
cv::Mat TexturedFrame() {
  cv::Mat noise(240, 320, CV_32FC1);
  cv::RNG(7).fill(noise, cv::RNG::NORMAL, 0.0, 1.0);
  cv::GaussianBlur(noise, noise, {0, 0}, 1.5);
  cv::Mat frame;
  noise.convertTo(frame, CV_8UC1, 40.0 / 0.19, 128.0);
  return frame;
}

// Mean |a − b| over the frame.
double MeanAbsDifference(const cv::Mat& a, const cv::Mat& b) {
  cv::Mat d;
  cv::absdiff(a, b, d);
  return cv::mean(d)[0];
}

TEST(JpegRoundTrip, LeavesTheFrameAtQuality0AndLosesMoreAtLowerQuality) {
  const cv::Mat frame = TexturedFrame();
  EXPECT_EQ(JpegRoundTrip(frame, 0).data, frame.data);
  const double at95 = MeanAbsDifference(JpegRoundTrip(frame, 95), frame);
  const double at70 = MeanAbsDifference(JpegRoundTrip(frame, 70), frame);
  const double at30 = MeanAbsDifference(JpegRoundTrip(frame, 30), frame);
  EXPECT_GT(at95, 0.1);
  EXPECT_LT(at95, at70);
  EXPECT_LT(at70, at30);
  EXPECT_LT(at70, 10.0);  // a degraded frame, not a different one
}

// The error a JPEG adds jumps across the 8 × 8 blocks' edges: between columns 8k − 1 and 8k it
// changes more than between neighbours inside a block.
TEST(JpegRoundTrip, ItsErrorJumpsAtTheEightPixelBlocksEdges) {
  const cv::Mat frame = TexturedFrame();
  cv::Mat error;
  cv::subtract(JpegRoundTrip(frame, 50), frame, error, cv::noArray(), CV_32F);
  double across = 0, inside = 0;
  int n_across = 0, n_inside = 0;
  for (int y = 0; y < error.rows; ++y) {
    for (int x = 1; x < error.cols; ++x) {
      const double jump = std::abs(error.at<float>(y, x) - error.at<float>(y, x - 1));
      if (x % 8 == 0) {
        across += jump;
        ++n_across;
      } else {
        inside += jump;
        ++n_inside;
      }
    }
  }
  EXPECT_GT(across / n_across, 1.3 * inside / n_inside);
}

TEST(JpegRoundTrip, AQualityOutside0To100IsRefusedByTheOptionsCheck) {
  SimOptions options;
  for (const int quality : {-1, 101}) {
    options.render.jpeg_quality = quality;
    EXPECT_NE(Validate(options).message().find("jpeg_quality"), std::string::npos) << quality;
  }
  options.render.jpeg_quality = 70;
  EXPECT_TRUE(Validate(options).ok());
}

}  // namespace
}  // namespace fleetloc::sim
