// One template's NCC over many views, through its cached spectrum or summed directly (see
// spectral_ncc.h).
#include "imaging/spectral_ncc.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "imaging/dft_size.h"
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
    : templ_size_(templ.size()), view_size_(view_size), dft_size_(EvenDftSize(view_size)) {
  CV_Assert(templ.type() == CV_32F && view_size.width >= templ.cols &&
            view_size.height >= templ.rows);
  cv::Scalar mean, deviation;
  cv::meanStdDev(templ, mean, deviation);
  templ_norm_ = deviation[0] * std::sqrt(static_cast<double>(templ.total()));
  templ_mean_ = static_cast<float>(mean[0]);
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
  // Σ(t − t̄)·v over each window is the numerator; the window's own spread the denominator, and
  // near-degenerate windows (where the transforms' rounding dominates) as OpenCV treats them.
  cv::Mat surface = correlation(cv::Rect({0, 0}, out)).clone();
  NormalizeBySpread(view, templ_size_, templ_mean_, templ_norm_, SpreadRule::kLikeOpenCv, surface);
  return surface;
}

cv::Mat SpectralNcc::SurfaceNear(const cv::Mat& view) const {
  CV_Assert(view.type() == CV_32F && view.cols >= templ_size_.width &&
            view.rows >= templ_size_.height);
  cv::Mat surface = CrossCorrelationSums(view, zero_mean_);
  NormalizeBySpread(view, templ_size_, templ_mean_, templ_norm_, SpreadRule::kLikeOpenCv, surface);
  return surface;
}

}  // namespace fleetloc::imaging
