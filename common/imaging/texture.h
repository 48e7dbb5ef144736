// Texture scoring (paper 000 §2.4.1): the smallest eigenvalue of the gradient structure matrix
// Σ_w [gx², gx·gy; gx·gy, gy²], which is large only where texture is two-dimensional (it rejects
// edges and stripes such as tile joints).
#pragma once

#include <opencv2/core.hpp>

namespace fleetloc::imaging {

// Returns a CV_32F image of the same size as `gray` (CV_8UC1 or CV_32F): per pixel, the smallest
// eigenvalue of the structure matrix summed over a window_px × window_px box (window_px odd ≥ 3),
// averaged over the window. Gradients are Sobel 3×3 in grey levels per pixel.
cv::Mat TextureScore(const cv::Mat& gray, int window_px);

}  // namespace fleetloc::imaging
