// One template's NCC over many views, through its cached spectrum or summed directly (see
// spectral_ncc.h).
#include "imaging/spectral_ncc.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "imaging/fast_patch.h"

namespace fleetloc::imaging {
namespace {

// A view's two transforms (forward, and the inverse of the product) against the direct sums'
// 8-wide multiply-adds: measured on one core of this Debian build, one transformed pixel costs
// about as much as 60 of them (154×114 frame: ±5 px directly 0.11 ms, through spectra 0.74 ms;
// ±14 px 0.96 and 0.90 ms; docs/benchmarks.md, session 43).
constexpr double kMultiplyAddsPerTransformedPixel = 60.0;

}  // namespace

SpectralNcc::SpectralNcc(const cv::Mat& templ, cv::Size view_size)
    : templ_size_(templ.size()),
      view_size_(view_size),
      dft_size_(cv::getOptimalDFTSize(view_size.width), cv::getOptimalDFTSize(view_size.height)) {
  CV_Assert(templ.type() == CV_32F && view_size.width >= templ.cols &&
            view_size.height >= templ.rows);
  cv::Scalar mean, deviation;
  cv::meanStdDev(templ, mean, deviation);
  templ_norm_ = deviation[0] * std::sqrt(static_cast<double>(templ.total()));
  // Padding to at least the view's size keeps the circular correlation exact wherever the
  // template lies wholly inside the view, which is every position of the surface.
  cv::Mat padded = cv::Mat::zeros(dft_size_, CV_32F);
  zero_mean_ = padded(cv::Rect({0, 0}, templ_size_));
  cv::subtract(templ, mean, zero_mean_);
  direct_ = CrossCorrelationSumsCost(view_size, templ_size_) <=
            kMultiplyAddsPerTransformedPixel * dft_size_.area();
  if (!direct_) cv::dft(padded, spectrum_, 0, templ.rows);
}

cv::Mat SpectralNcc::Surface(const cv::Mat& view) const {
  CV_Assert(view.type() == CV_32F && view.size() == view_size_);
  if (direct_) return SurfaceNear(view);
  const cv::Size out(view.cols - templ_size_.width + 1, view.rows - templ_size_.height + 1);
  cv::Mat padded = cv::Mat::zeros(dft_size_, CV_32F), spectrum, correlation;
  view.copyTo(padded(cv::Rect({0, 0}, view_size_)));
  cv::dft(padded, spectrum, 0, view.rows);
  cv::mulSpectrums(spectrum, spectrum_, spectrum, 0, /*conjB=*/true);
  cv::idft(spectrum, correlation, cv::DFT_SCALE | cv::DFT_REAL_OUTPUT, out.height);
  return Normalized(view, correlation(cv::Rect({0, 0}, out)));
}

cv::Mat SpectralNcc::SurfaceNear(const cv::Mat& view) const {
  CV_Assert(view.type() == CV_32F && view.cols >= templ_size_.width &&
            view.rows >= templ_size_.height);
  const cv::Mat correlation = CrossCorrelationSums(view, zero_mean_);
  return Normalized(view, correlation);
}

// Σ(t − t̄)·v over each window (`correlation`) is the numerator; the window's own spread the
// denominator, from integral images in double as OpenCV's; near-degenerate windows as OpenCV
// treats them.
cv::Mat SpectralNcc::Normalized(const cv::Mat& view, const cv::Mat& correlation) const {
  const cv::Size out = correlation.size();
  cv::Mat sum, square_sum;
  cv::integral(view, sum, square_sum, CV_64F, CV_64F);
  const double n = static_cast<double>(templ_size_.area());
  const int w = templ_size_.width, h = templ_size_.height;
  cv::Mat surface(out, CV_32F);
  for (int y = 0; y < out.height; ++y) {
    const double *s0 = sum.ptr<double>(y), *s1 = sum.ptr<double>(y + h);
    const double *q0 = square_sum.ptr<double>(y), *q1 = square_sum.ptr<double>(y + h);
    const float* c = correlation.ptr<float>(y);
    float* o = surface.ptr<float>(y);
    for (int x = 0; x < out.width; ++x) {
      const double window_sum = s1[x + w] - s1[x] - s0[x + w] + s0[x];
      const double window_sq = q1[x + w] - q1[x] - q0[x + w] + q0[x];
      const double t =
          std::sqrt(std::max(window_sq - window_sum * window_sum / n, 0.0)) * templ_norm_;
      double num = c[x];
      if (std::abs(num) < t) {
        num /= t;
      } else if (std::abs(num) < t * 1.125) {
        num = num > 0 ? 1.0 : -1.0;
      } else {
        num = 0.0;
      }
      o[x] = static_cast<float>(num);
    }
  }
  return surface;
}

}  // namespace fleetloc::imaging
