// Each frame pixel's residual precision under local normalization (issue 15). Dividing a pixel by
// its neighbourhood's spread s(x) equalizes the texture's contrast across the frame, and the
// sensor noise with it: in the normalized frame a pixel's noise is σ_n / s(x). Where the noise is
// small against the texture, every pixel's residual has about the same spread (what remains,
// blur and interpolation, scales with the normalized texture), and equal weights are right; under
// a short exposure's noise the low-contrast pixels are mostly noise and deserve less weight than
// the rest. The residual variance is modelled as A + B·u(x), u = 1/s(x)², fitted to each frame's
// residuals at the start pose; the precision of a pixel relative to the median one is then
// (A + B·ū)/(A + B·u(x)). Where the residuals do not grow with u (occluders, whose edges raise
// contrast and residual together) the fit has no noise term and every weight stays 1.
// The fit does not tell sensor noise from other residuals that grow where contrast is low (fine
// texture the frame's blur has removed): such pixels hold less of the floor, and count less too.
#pragma once

#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>
#include <vector>

namespace fleetloc::tracking {

// Residual variance A + B·u over a frame's pixels; `median_u` is the median pixel's u.
struct ResidualNoise {
  double a = 0.0, b = 0.0, median_u = 0.0;
  // Precision of a pixel at `u` relative to the median pixel's.
  double Precision(double u) const { return (a + b * median_u) / (a + b * u); }
};

// u = 1/(√local_variance + epsilon)²: the square of the factor local normalization
// (imaging::NormalizePatch with that epsilon) multiplied a pixel by.
inline float NormalizationFactorSquared(float local_variance, float epsilon) {
  const float d = std::sqrt(std::max(local_variance, 0.0f)) + epsilon;
  return 1.0f / (d * d);
}

// The fit over a sparse grid of the frame: `frame`, `inner`, `spans` and `view` (with its
// one-pixel border) as LinearizeWholeFrame's arguments (tracking/dense_linearization.h),
// `local_variance` (the frame's size) and `epsilon` as the normalization's. The residuals t −
// gain·v (gain their least-squares contrast) are cut into bins by u; the line through the bins'
// variances (robust: their medians) gives A and B. B < 0 is taken as 0, and A at least a tenth of
// the lowest bin's variance.
ResidualNoise FitResidualNoise(const cv::Mat& frame, const cv::Mat& view, const cv::Rect& inner,
                               const std::vector<cv::Range>& spans, const cv::Mat& local_variance,
                               float epsilon);

// The relative precision of every pixel (CV_32F, local_variance's size) under `noise`; empty,
// and nothing computed, when the fit has no noise term (every pixel 1).
cv::Mat ResidualPrecision(const ResidualNoise& noise, const cv::Mat& local_variance, float epsilon);

}  // namespace fleetloc::tracking
