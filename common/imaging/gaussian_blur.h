// A Gaussian blur of a float image over the pixels whose whole kernel lies inside it: the
// tracker's polish blurs a frame-sized mosaic view to the frame's blur at every linearization
// (see tracking/view_blur.h), and only keeps the pixels away from the view's margin.
#pragma once

#include <opencv2/core.hpp>

namespace fleetloc::imaging {

// `src` (CV_32FC1) convolved with the Gaussian of `sigma_px` (> 0) and radius `radius_px` (≥ 0),
// cv::getGaussianKernel's taps in both directions, at the pixels at least radius_px from every
// side: returns (rows − 2r) × (cols − 2r), equal to cv::GaussianBlur with a (2r + 1)² kernel
// cropped by r, up to float rounding. src must be larger than 2r in both directions.
cv::Mat GaussianBlurInterior(const cv::Mat& src, double sigma_px, int radius_px);

}  // namespace fleetloc::imaging
