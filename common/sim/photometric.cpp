// Photometric effects of the simulated camera.
#include "sim/photometric.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace fleetloc::sim {
namespace {

constexpr double kMinMotionBlurPx = 0.05;
constexpr int kLightingGridCols = 4;  // coarse light grid, interpolated bicubically
constexpr int kLightingGridRows = 3;

}  // namespace

SensorDraw DrawSensor(const RenderOptions& options, cv::RNG& rng) {
  SensorDraw draw;
  draw.gain = options.gain_min < options.gain_max ? rng.uniform(options.gain_min, options.gain_max)
                                                  : options.gain_min;
  draw.bias_dn = options.bias_min_dn < options.bias_max_dn
                     ? rng.uniform(options.bias_min_dn, options.bias_max_dn)
                     : options.bias_min_dn;
  return draw;
}

cv::Mat LightingField(cv::Size size, double amplitude, cv::RNG& rng) {
  if (amplitude <= 0) return cv::Mat::ones(size, CV_32FC1);
  cv::Mat grid(kLightingGridRows, kLightingGridCols, CV_32FC1);
  rng.fill(grid, cv::RNG::UNIFORM, -1.0, 1.0);
  cv::Mat blobs;
  cv::resize(grid, blobs, size, 0, 0, cv::INTER_CUBIC);
  // A random gradient from -1 to 1 across the image, in a random direction.
  const double angle = rng.uniform(0.0, 2.0 * M_PI);
  const double gx = std::cos(angle) / (0.5 * size.width),
               gy = std::sin(angle) / (0.5 * size.height);
  cv::Mat field(size, CV_32FC1);
  for (int v = 0; v < size.height; ++v) {
    const float* b = blobs.ptr<float>(v);
    float* f = field.ptr<float>(v);
    for (int u = 0; u < size.width; ++u) {
      const double ramp = gx * (u + 0.5 - 0.5 * size.width) + gy * (v + 0.5 - 0.5 * size.height);
      f[u] = static_cast<float>(1.0 + amplitude * std::clamp(0.5 * (ramp + b[u]), -1.0, 1.0));
    }
  }
  return field;
}

cv::Mat VignettingField(const geometry::CameraModel& camera, double corner_loss) {
  const cv::Size size(camera.width_px, camera.height_px);
  if (corner_loss <= 0) return cv::Mat::ones(size, CV_32FC1);
  // cos^4(atan(r / f)) = 1 / (1 + (r / f)²)²; choose f so the farthest corner keeps 1 - loss.
  const double corner_r = std::hypot(std::max(camera.cx_px, camera.width_px - camera.cx_px),
                                     std::max(camera.cy_px, camera.height_px - camera.cy_px));
  const double focal_px = corner_r / std::sqrt(1.0 / std::sqrt(1.0 - corner_loss) - 1.0);
  cv::Mat field(size, CV_32FC1);
  for (int v = 0; v < size.height; ++v) {
    float* f = field.ptr<float>(v);
    for (int u = 0; u < size.width; ++u) {
      const double r2 =
          (std::pow(u + 0.5 - camera.cx_px, 2) + std::pow(v + 0.5 - camera.cy_px, 2)) /
          (focal_px * focal_px);
      f[u] = static_cast<float>(1.0 / ((1.0 + r2) * (1.0 + r2)));
    }
  }
  return field;
}

cv::Mat MotionBlurKernel(const Eigen::Vector2d& displacement_px) {
  const double length = displacement_px.norm();
  if (length < kMinMotionBlurPx) return cv::Mat::ones(1, 1, CV_32FC1);
  const int half = static_cast<int>(std::ceil(0.5 * std::abs(displacement_px.x()))) + 1;
  const int half_v = static_cast<int>(std::ceil(0.5 * std::abs(displacement_px.y()))) + 1;
  cv::Mat kernel = cv::Mat::zeros(2 * half_v + 1, 2 * half + 1, CV_32FC1);
  // Splat evenly spaced points along the segment with bilinear weights.
  const int samples = static_cast<int>(std::ceil(8.0 * length)) + 1;
  for (int i = 0; i < samples; ++i) {
    const Eigen::Vector2d p = displacement_px * (static_cast<double>(i) / (samples - 1) - 0.5) +
                              Eigen::Vector2d(half, half_v);
    const int x0 = static_cast<int>(std::floor(p.x())), y0 = static_cast<int>(std::floor(p.y()));
    const double fx = p.x() - x0, fy = p.y() - y0;
    kernel.at<float>(y0, x0) += static_cast<float>((1 - fx) * (1 - fy));
    kernel.at<float>(y0, x0 + 1) += static_cast<float>(fx * (1 - fy));
    kernel.at<float>(y0 + 1, x0) += static_cast<float>((1 - fx) * fy);
    kernel.at<float>(y0 + 1, x0 + 1) += static_cast<float>(fx * fy);
  }
  return kernel / cv::sum(kernel)[0];
}

int MarginForBlur(double sigma_px, const Eigen::Vector2d& displacement_px) {
  return static_cast<int>(std::ceil(4.0 * sigma_px + 0.5 * displacement_px.cwiseAbs().maxCoeff())) +
         2;
}

void ApplyBlur(double sigma_px, const Eigen::Vector2d& displacement_px, cv::Mat* image) {
  if (sigma_px > 0)
    cv::GaussianBlur(*image, *image, cv::Size(), sigma_px, sigma_px, cv::BORDER_REFLECT);
  const cv::Mat kernel = MotionBlurKernel(displacement_px);
  if (kernel.total() > 1)
    cv::filter2D(*image, *image, -1, kernel, cv::Point(-1, -1), 0, cv::BORDER_REFLECT);
}

cv::Mat ApplySensor(const cv::Mat& irradiance, const SensorDraw& draw, const RenderOptions& options,
                    cv::RNG& rng) {
  cv::Mat signal = irradiance * draw.gain;
  if (options.noise_sigma_dn > 0 || options.shot_noise_dn > 0) {
    cv::Mat noise(signal.size(), CV_32FC1);
    rng.fill(noise, cv::RNG::NORMAL, 0.0, 1.0);
    cv::Mat variance = cv::max(signal, 0.0) * options.shot_noise_dn +
                       options.noise_sigma_dn * options.noise_sigma_dn;
    cv::sqrt(variance, variance);
    signal += noise.mul(variance);
  }
  const bool identity_response = options.response_gamma == 1.0 && options.response_s_curve == 0.0;
  if (!identity_response) {
    cv::Mat x = cv::min(cv::max(signal * (1.0 / 255.0), 0.0), 1.0);
    cv::pow(x, options.response_gamma, x);
    const cv::Mat smooth = x.mul(x).mul(3.0 - 2.0 * x);
    signal = ((1.0 - options.response_s_curve) * x + options.response_s_curve * smooth) * 255.0;
  }
  cv::Mat out;
  signal.convertTo(out, CV_8UC1, 1.0, draw.bias_dn);  // rounds and saturates
  return out;
}

}  // namespace fleetloc::sim
