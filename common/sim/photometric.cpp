// Photometric effects of the simulated camera.
#include "sim/photometric.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <opencv2/core/hal/intrin.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <vector>

namespace fleetloc::sim {
namespace {

constexpr double kMinMotionBlurPx = 0.05;
constexpr int kLightingGridCols = 4;  // coarse light grid, interpolated bicubically
constexpr int kLightingGridRows = 3;
constexpr int kLightingCellPx = 8;  // the light field is computed every 8 pixels, interpolated
constexpr int kResponseEntries = 1024;

// The camera response y = 255 · ((1 - s) · x^γ + s · smoothstep(x^γ)), x = signal / 255 clamped
// to [0, 1], tabulated and interpolated linearly; the identity when γ = 1 and s = 0.
class ResponseCurve {
 public:
  ResponseCurve(double gamma, double s_curve) : identity_(gamma == 1.0 && s_curve == 0.0) {
    if (identity_) return;
    table_.resize(kResponseEntries + 2);
    for (int i = 0; i <= kResponseEntries; ++i) {
      const double x = std::pow(static_cast<double>(i) / kResponseEntries, gamma);
      table_[i] =
          static_cast<float>(255.0 * ((1.0 - s_curve) * x + s_curve * x * x * (3.0 - 2.0 * x)));
    }
    table_[kResponseEntries + 1] = table_[kResponseEntries];  // guard for the interpolation
  }
  float operator()(float signal_dn) const {
    if (identity_) return signal_dn;
    const float x = std::clamp(signal_dn, 0.0f, 255.0f) * (kResponseEntries / 255.0f);
    const auto i = static_cast<int>(x);
    return table_[i] + (x - static_cast<float>(i)) * (table_[i + 1] - table_[i]);
  }

 private:
  bool identity_;
  std::vector<float> table_;
};

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
  if (amplitude <= 0) return {};
  // Evaluated on a coarse grid and interpolated: the field has no detail finer than that.
  const cv::Size coarse(size.width / kLightingCellPx + 2, size.height / kLightingCellPx + 2);
  cv::Mat grid(kLightingGridRows, kLightingGridCols, CV_32FC1);
  rng.fill(grid, cv::RNG::UNIFORM, -1.0, 1.0);
  cv::Mat blobs;
  cv::resize(grid, blobs, coarse, 0, 0, cv::INTER_CUBIC);
  // A random gradient from -1 to 1 across the image, in a random direction.
  const double angle = rng.uniform(0.0, 2.0 * M_PI);
  const double gx = 2.0 * std::cos(angle) / (coarse.width - 1);
  const double gy = 2.0 * std::sin(angle) / (coarse.height - 1);
  cv::Mat field(coarse, CV_32FC1);
  for (int v = 0; v < coarse.height; ++v) {
    for (int u = 0; u < coarse.width; ++u) {
      const double ramp =
          gx * (u - 0.5 * (coarse.width - 1)) + gy * (v - 0.5 * (coarse.height - 1));
      field.at<float>(v, u) = static_cast<float>(
          1.0 + amplitude * std::clamp(0.5 * (ramp + blobs.at<float>(v, u)), -1.0, 1.0));
    }
  }
  cv::resize(field, field, size, 0, 0, cv::INTER_LINEAR);
  return field;
}

cv::Mat VignettingField(const geometry::CameraModel& camera, double corner_loss) {
  const cv::Size size(camera.width_px, camera.height_px);
  if (corner_loss <= 0) return {};
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

namespace {

// One row of the sensor before the response curve: signal = gain · radiance · shading plus noise of
// variance read + shot · signal, into `signal`. `shading` and `noise` may be null (none).
void SensorSignalRow(const float* radiance, const float* shading, const float* noise, int width,
                     float gain, float read_variance, float shot, float* signal) {
  int u = 0;
#if CV_SIMD128
  const cv::v_float32x4 v_gain = cv::v_setall_f32(gain), v_read = cv::v_setall_f32(read_variance);
  const cv::v_float32x4 v_shot = cv::v_setall_f32(shot), zero = cv::v_setzero_f32();
  for (; u + 4 <= width; u += 4) {
    cv::v_float32x4 value = cv::v_load(radiance + u) * v_gain;
    if (shading != nullptr) value = value * cv::v_load(shading + u);
    if (noise != nullptr) {
      const cv::v_float32x4 sigma =
          cv::v_sqrt(cv::v_muladd(cv::v_max(value, zero), v_shot, v_read));
      value = cv::v_muladd(cv::v_load(noise + u), sigma, value);
    }
    cv::v_store(signal + u, value);
  }
#endif
  for (; u < width; ++u) {
    float value = gain * radiance[u] * (shading != nullptr ? shading[u] : 1.0f);
    if (noise != nullptr)
      value += noise[u] * std::sqrt(read_variance + shot * std::max(value, 0.0f));
    signal[u] = value;
  }
}

}  // namespace

cv::Mat ApplySensor(const cv::Mat& radiance, const cv::Mat& shading, const SensorDraw& draw,
                    const RenderOptions& options, cv::RNG& rng) {
  CV_Assert(radiance.type() == CV_32FC1);
  CV_Assert(shading.empty() || (shading.type() == CV_32FC1 && shading.size() == radiance.size()));
  const bool noisy = options.noise_sigma_dn > 0 || options.shot_noise_dn > 0;
  const ResponseCurve response(options.response_gamma, options.response_s_curve);
  cv::Mat noise(1, radiance.cols, CV_32FC1), signal(1, radiance.cols, CV_32FC1);  // row buffers
  cv::Mat out(radiance.size(), CV_8UC1);
  for (int v = 0; v < radiance.rows; ++v) {
    if (noisy) rng.fill(noise, cv::RNG::NORMAL, 0.0, 1.0);
    auto* row = signal.ptr<float>();
    SensorSignalRow(radiance.ptr<float>(v), shading.empty() ? nullptr : shading.ptr<float>(v),
                    noisy ? noise.ptr<float>() : nullptr, radiance.cols,
                    static_cast<float>(draw.gain),
                    static_cast<float>(options.noise_sigma_dn * options.noise_sigma_dn),
                    static_cast<float>(options.shot_noise_dn), row);
    for (int u = 0; u < radiance.cols; ++u) row[u] = response(row[u]);
    signal.convertTo(out.row(v), CV_8UC1, 1.0, draw.bias_dn);  // rounds and saturates
  }
  return out;
}

cv::Mat JpegRoundTrip(const cv::Mat& frame, int quality) {
  CV_Assert(frame.type() == CV_8UC1 && quality >= 0 && quality <= 100);
  if (quality == 0) return frame;
  std::vector<uchar> encoded;
  CV_Assert(cv::imencode(".jpg", frame, encoded, {cv::IMWRITE_JPEG_QUALITY, quality}));
  return cv::imdecode(encoded, cv::IMREAD_GRAYSCALE);
}

}  // namespace fleetloc::sim
