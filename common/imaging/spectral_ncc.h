// Normalized cross-correlation (OpenCV's TM_CCOEFF_NORMED, the same numbers) of one template over
// many same-sized views, with the template's spectrum computed once. cv::matchTemplate takes the
// template's DFT again on every call; the dense alignment's coarse search correlates one frame
// with up to 2 + max_heading_steps views (one per heading tried), so a third of its DFTs were
// repeats. The sums are OpenCV's (cv::dft, cv::mulSpectrums, cv::integral). Where the views are
// only a few pixels larger than the template, the products are summed directly instead
// (CrossCorrelationSums, fast_patch.h): this Debian build's cv::dft (no IPP) takes ~0.4 ms a
// transform of a 180×135 view on one core, and a ±5 px search of a 154×114 frame sums directly in
// ~0.1 ms (docs/benchmarks.md, session 43). Its mirror is MaskedCorrelator: one fixed image (the
// mosaic) and many masked templates, TM_CCORR_NORMED.
#pragma once

#include <opencv2/core.hpp>

namespace fleetloc::imaging {

class SpectralNcc {
 public:
  // `templ`: CV_32F. Views passed to Surface must have `view_size` (≥ the template's size).
  SpectralNcc(const cv::Mat& templ, cv::Size view_size);

  // The NCC surface of the template over `view` (CV_32F, view_size): CV_32F,
  // (view − template + 1) in each axis, as cv::matchTemplate(view, templ, TM_CCOEFF_NORMED).
  cv::Mat Surface(const cv::Mat& view) const;

  // The same surface over a view of any size ≥ the template's, summed directly instead of through
  // the spectrum: for views a few pixels larger than the template (a peak's neighbourhood), where
  // it costs a fraction of Surface's two transforms.
  cv::Mat SurfaceNear(const cv::Mat& view) const;

 private:
  cv::Size templ_size_, view_size_, dft_size_;
  bool direct_ = false;      // views summed directly (CrossCorrelationSums), not through spectra
  cv::Mat spectrum_;         // of the zero-mean template, padded to dft_size_ (CCS packed)
  cv::Mat zero_mean_;        // the zero-mean template
  double templ_norm_ = 0.0;  // √Σ(t − t̄)²
  float templ_mean_ = 0.0f;
};

}  // namespace fleetloc::imaging
