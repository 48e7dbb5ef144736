// Texture score via cv::cornerMinEigenVal, which computes exactly the smallest eigenvalue of the
// box-summed structure matrix (vectorized); we only undo its gradient scaling.
#include "imaging/texture.h"

#include <opencv2/imgproc.hpp>

namespace fleetloc::imaging {

cv::Mat TextureScore(const cv::Mat& gray, int window_px) {
  CV_Assert(window_px >= 3 && window_px % 2 == 1);
  CV_Assert(gray.type() == CV_8UC1 || gray.type() == CV_32FC1);
  cv::Mat score;
  cv::cornerMinEigenVal(gray, score, window_px, 3, cv::BORDER_REFLECT);
  // OpenCV scales the 3×3 Sobel by 1/(4·window) (and 1/255 for 8-bit input) and sums the
  // products unnormalized over the window. Undo that so the score is the window mean of the
  // structure matrix with gradients in grey levels per pixel (Sobel/8).
  const double sobel_scale = 1.0 / (4.0 * window_px) * (gray.depth() == CV_8U ? 1.0 / 255.0 : 1.0);
  const double to_per_pixel = 1.0 / (8.0 * sobel_scale);
  score *= to_per_pixel * to_per_pixel / (window_px * window_px);
  return score;
}

}  // namespace fleetloc::imaging
