// The camera's photometric effects on a rendered floor image (CV_32FC1, DN): uneven lighting,
// vignetting, lens and motion blur, and the sensor (gain, shot and read noise, response curve,
// bias, 8-bit quantization).
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "geometry/camera_model.h"
#include "sim/sim_options.h"

namespace fleetloc::sim {

// One frame's random sensor settings.
struct SensorDraw {
  double gain = 1.0;
  double bias_dn = 0.0;
};

// Draws gain and bias uniformly within the options' ranges.
SensorDraw DrawSensor(const RenderOptions& options, cv::RNG& rng);

// A smooth multiplicative light field of `size`: 1 + amplitude · f with |f| ≤ 1, made of a random
// linear gradient and a coarse random grid interpolated bicubically. Empty (no change) for
// amplitude 0.
cv::Mat LightingField(cv::Size size, double amplitude, cv::RNG& rng);

// cos^4 falloff around the principal point, scaled so that the image corners lose
// `corner_loss` of their brightness. Empty (no change) for corner_loss 0.
cv::Mat VignettingField(const geometry::CameraModel& camera, double corner_loss);

// The normalized line kernel of a uniform motion by `displacement_px` (centred: the frame time is
// the middle of the exposure); a 1×1 identity for displacements under 0.05 px.
cv::Mat MotionBlurKernel(const Eigen::Vector2d& displacement_px);

// Lens blur (Gaussian, skipped for sigma 0) then motion blur, in place; edges are reflected, so
// give the image a margin of MarginForBlur() pixels and crop it afterwards.
void ApplyBlur(double sigma_px, const Eigen::Vector2d& displacement_px, cv::Mat* image);
int MarginForBlur(double sigma_px, const Eigen::Vector2d& displacement_px);

// The sensor: signal = gain · radiance · shading (shading: lighting × vignetting, or empty for
// none), plus Gaussian noise of variance noise_sigma_dn² + shot_noise_dn · signal, through the
// response curve y = 255 · ((1 - s) · x^γ + s · smoothstep(x^γ)) with x = signal / 255, plus the
// bias, rounded and saturated to 8 bits.
cv::Mat ApplySensor(const cv::Mat& radiance, const cv::Mat& shading, const SensorDraw& draw,
                    const RenderOptions& options, cv::RNG& rng);

// The 8-bit frame JPEG-encoded at `quality` (1..100) and decoded again (in memory): a streaming
// camera's compression. The frame itself for quality 0.
cv::Mat JpegRoundTrip(const cv::Mat& frame, int quality);

}  // namespace fleetloc::sim
