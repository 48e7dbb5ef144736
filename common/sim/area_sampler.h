// Area-sensor sampling of an 8-bit raster under an affine map: each output pixel is the mean of
// k × k bilinear samples spread evenly over the pixel, i.e. exactly what rendering k times larger
// with bilinear warping and averaging k × k blocks (cv::warpAffine + cv::resize INTER_AREA) gives,
// but computed as one 4×4-ish weighted sum per output pixel with weights tabulated per frame for
// 1/64-pixel phases. That is several times faster than warping k² as many pixels, and its
// sample positions are exact to 1/128 pixel (cv::warpAffine rounds them to 1/32).
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>

namespace fleetloc::sim {

class AreaSampler {
 public:
  // `pixel_to_source` maps continuous output coordinates (pixel (i, j) has its centre at
  // (i + 0.5, j + 0.5)) to continuous source coordinates (same convention); `supersample` ≥ 1.
  AreaSampler(const Eigen::Matrix<double, 2, 3>& pixel_to_source, int supersample);

  // The source pixels that sampling an output of `size` reads: read at least this rect.
  cv::Rect SourceRect(cv::Size size) const;

  // Samples `source` (CV_8UC1, whose pixel (0, 0) is source pixel `source_rect.tl()`, covering
  // SourceRect(size)) into a CV_32FC1 image of `size`.
  cv::Mat Sample(const cv::Mat& source, const cv::Rect& source_rect, cv::Size size) const;

 private:
  static constexpr int kPhaseBits = 6;
  static constexpr int kPhases = 1 << kPhaseBits;  // tabulated sub-pixel phases per axis

  Eigen::Matrix<double, 2, 3> to_index_;  // output continuous coords → source index coords
  int first_tap_ = 0;                     // support of one output pixel: taps first .. first+size-1
  int taps_ = 0;                          // relative to floor(index of the pixel centre)
  std::vector<float> weights_;            // [phase_y][phase_x][tap_y][tap_x]
};

}  // namespace fleetloc::sim
