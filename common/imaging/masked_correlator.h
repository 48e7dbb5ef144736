// Masked normalized cross-correlation of many templates with one fixed image: the numerator
// Σ T·M·I by FFT with the image's spectrum computed once (cv::matchTemplate with a mask transforms
// the image again on every call), the denominator's Σ M·I² from the image's row prefix sums of I²
// (two shifted sums a row of the mask, no transform). Each template costs one forward and one
// inverse transform, and the same template turned by π one inverse transform more (a correlation
// with the template flipped about its centre is a convolution with the template). Used by the
// dense place search, which correlates one normalized mosaic with a frame at every heading (θ and
// θ + π together).
#pragma once

#include <opencv2/core.hpp>

namespace fleetloc::imaging {

class MaskedCorrelator {
 public:
  // `image`: CV_32FC1, not empty, and zero within `zero_border_px` of each side (checked; less
  // than half its short side): the transforms are that much shorter, as a cyclic correlation may
  // then wrap into the border's zeros. Templates must be larger than zero_border_px both ways
  // (checked).
  explicit MaskedCorrelator(const cv::Mat& image, int zero_border_px = 0);

  // The same as cv::matchTemplate(image, templ, *scores, cv::TM_CCORR_NORMED, mask) up to float
  // rounding: scores (CV_32F, (W − w + 1) × (H − h + 1)) at every placement of the template's
  // top-left corner, Σ T·M·I / sqrt(Σ (T·M)² · Σ M·I²). `templ` CV_32FC1 and `mask` CV_8UC1
  // (non-zero: used) of the same size, no larger than the image (checked). Where the mask covers
  // only zeros of the image the quotient is 0/0: NaN, infinite or 0 (the caller patches it).
  void Match(const cv::Mat& templ, const cv::Mat& mask, cv::Mat* scores) const;
  // Match, and into *turned_scores the scores of the template and mask turned by π (cv::flip about
  // both axes), from the same forward transform: one inverse transform more than Match. A mask
  // that its turn leaves unchanged (a rotated rectangle's) shares the denominator too.
  void MatchWithTurned(const cv::Mat& templ, const cv::Mat& mask, cv::Mat* scores,
                       cv::Mat* turned_scores) const;

  cv::Size image_size() const { return image_size_; }
  std::size_t MemoryBytes() const;

 private:
  void CheckLargerThanZeroBorder(const cv::Mat& templ) const;

  cv::Size image_size_, dft_size_;
  int zero_border_px_ = 0;
  cv::Mat spectrum_;     // CCS-packed spectrum of I, dft_size_
  cv::Mat row_sums_sq_;  // row prefix sums of I²: (W + 1) × H, (y, x) = Σ_{x' < x} I(y, x')²
};

// The same as cv::matchTemplate(image, templ, *scores, cv::TM_CCORR_NORMED, mask) up to float
// rounding, by one dot product per placement (Σ M·I² from the image's row prefix sums, as in
// MaskedCorrelator): faster than the transforms when there are only a few placements (the dense
// place search's refinement: 9 × 9 of a 200-pixel template).
// The same input rules as MaskedCorrelator::Match.
void MatchAtFewPlacements(const cv::Mat& image, const cv::Mat& templ, const cv::Mat& mask,
                          cv::Mat* scores);

}  // namespace fleetloc::imaging
