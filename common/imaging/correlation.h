// Template matching (paper 000 §2.7): normalized cross-correlation of a template over a search
// window, the sub-pixel peak, and the peak's quality (value, flatness, ambiguity).
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>

namespace fleetloc::imaging {

struct PeakOptions {
  // Second peaks closer than this to the best one belong to the same peak.
  int exclusion_radius_px = 3;
};

struct Match {
  bool found = false;
  // Sub-pixel position of the template's top-left corner inside the search window.
  Eigen::Vector2d offset_px{0, 0};
  double peak = 0.0;          // NCC at the best integer position, in [-1, 1]
  double second_peak = -1.0;  // best NCC outside the exclusion radius (-1 if none)
  double curvature = 0.0;     // smaller principal curvature of the NCC surface at the peak (> 0)
};

// Brute-force NCC (cv::matchTemplate, TM_CCOEFF_NORMED — OpenCV's vectorized implementation is
// the hot loop) of `templ` over `window` (both CV_32F, window ≥ template). `found` is false only
// when the surface is degenerate (no interior peak).
Match MatchTemplate(const cv::Mat& window, const cv::Mat& templ, const PeakOptions& options = {});

// Sub-pixel peak of a correlation surface around integer maximum `peak` (not on the border):
// a least-squares quadratic fitted to the 3×3 neighbourhood. Returns the offset from `peak`
// (each component clamped to ±1) and the smaller principal curvature (−λmax of the Hessian).
struct SubpixelPeak {
  Eigen::Vector2d offset{0, 0};
  double curvature = 0.0;
};
SubpixelPeak RefinePeak(const cv::Mat& surface, cv::Point peak);

}  // namespace fleetloc::imaging
