// Masked normalized cross-correlation of many templates with one fixed image, by FFT: the image's
// spectra (of I and of I²) are computed once, so each template costs two forward and two inverse
// transforms (cv::matchTemplate with a mask transforms the image again on every call). Used by the
// dense place search, which correlates one normalized mosaic with a frame at every heading.
#pragma once

#include <opencv2/core.hpp>

namespace fleetloc::imaging {

class MaskedCorrelator {
 public:
  // `image`: CV_32FC1, not empty.
  explicit MaskedCorrelator(const cv::Mat& image);

  // The same as cv::matchTemplate(image, templ, *scores, cv::TM_CCORR_NORMED, mask) up to float
  // rounding: scores (CV_32F, (W − w + 1) × (H − h + 1)) at every placement of the template's
  // top-left corner, Σ T·M·I / sqrt(Σ (T·M)² · Σ M·I²). `templ` CV_32FC1 and `mask` CV_8UC1
  // (non-zero: used) of the same size, no larger than the image (checked). Where the mask covers
  // only zeros of the image the quotient is 0/0: NaN, infinite or 0 (the caller patches it).
  void Match(const cv::Mat& templ, const cv::Mat& mask, cv::Mat* scores) const;

  cv::Size image_size() const { return image_size_; }
  std::size_t MemoryBytes() const;

 private:
  cv::Size image_size_, dft_size_;
  cv::Mat spectrum_, spectrum_sq_;  // CCS-packed spectra of I and I², dft_size_
};

}  // namespace fleetloc::imaging
