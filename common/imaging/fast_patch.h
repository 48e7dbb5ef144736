// Small-patch kernels for the tracker's hot loop: local normalization, direct NCC and a grid
// texture score (bilinear affine resampling: resample.h). Written by hand rather than calling
// OpenCV because on the 40–80 px patches the tracker works on, OpenCV's per-call cost dominates:
// measured on this Debian build (one core), cv::warpAffine of a 48² patch takes 19 µs,
// cv::boxFilter 9 µs, cv::matchTemplate goes through a DFT and takes ≥ 50 µs even for a ±2 px
// search, and cv::cornerMinEigenVal takes 1.1 ms on a 320×240 image when only a grid of points is
// needed. These loops do the same arithmetic in a few µs (contiguous inner loops the compiler
// vectorizes). Their results are checked against the OpenCV functions in fast_patch_test.cpp.
#pragma once

#include <opencv2/core.hpp>

namespace fleetloc::imaging {

// (I − μ_w) / (σ_w + ε) with an odd window_px; the window is clipped at the patch border (the
// caller normalizes a patch with a margin and crops it). Input CV_8UC1 or CV_32FC1; returns CV_32F.
// `local_variance`, when given, receives σ_w² (CV_32F, grey levels²), which the normalization
// computes anyway.
cv::Mat NormalizePatch(const cv::Mat& patch, int window_px, float epsilon = 2.0f,
                       cv::Mat* local_variance = nullptr);

// The TM_CCOEFF_NORMED surface of `templ` over `window` (both CV_32F), computed directly:
// (window − templ + 1) positions. Cost ∝ positions × template pixels: meant for small searches.
cv::Mat NccSurface(const cv::Mat& window, const cv::Mat& templ);

// Σ t·v at every placement of `templ` over `window` (both CV_32F): NccSurface's numerator for a
// zero-mean template, (window − templ + 1) positions summed directly.
cv::Mat CrossCorrelationSums(const cv::Mat& window, const cv::Mat& templ);

// What a placement whose Σ t'·v reaches the window's spread (rounding, a flat window) becomes.
enum class SpreadRule {
  kZeroWhenFlat,  // c / spread, 0 where the spread is 0 (NccSurface)
  kLikeOpenCv,    // as TM_CCOEFF_NORMED: ±1 up to 1.125 × the spread, 0 beyond (sums with a
                  // transform's rounding in them, SpectralNcc)
};

// Divides each placement's Σ t'·v (`cross`, CV_32F, in place) by the spread of `window` under it
// times `templ_norm` (‖t − t̄‖): the normalized cross-correlation. The window's sums are of
// v − `offset` in double (the template's mean keeps them small on bright images, where Σ v²
// would leave few digits for the spread); running sums, not integral images (cv::integral in
// double cost ten times as much on a coarse search's view).
void NormalizeBySpread(const cv::Mat& window, cv::Size templ, float offset, double templ_norm,
                       SpreadRule rule, cv::Mat& cross);

// What CrossCorrelationSums costs, in 8-wide multiply-adds, for these sizes.
double CrossCorrelationSumsCost(cv::Size window, cv::Size templ);

// Texture score at grid points: element (r, c) is taken at pixel ((c + 1)·step, (r + 1)·step):
// the smallest eigenvalue of the window-mean structure matrix of central-difference gradients
// (grey levels per pixel). Returns CV_32F of (rows/step − 1) × (cols/step − 1); points whose
// window leaves the image score 0. `gray` CV_8UC1.
cv::Mat TextureScoreGrid(const cv::Mat& gray, int step_px, int window_px);

}  // namespace fleetloc::imaging
