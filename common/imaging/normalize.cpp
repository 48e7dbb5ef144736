// Local normalization with box filters (vectorized by OpenCV).
#include "imaging/normalize.h"

#include <opencv2/imgproc.hpp>

namespace fleetloc::imaging {

cv::Mat LocalNormalize(const cv::Mat& gray, int window_px, float epsilon) {
  CV_Assert(window_px >= 3 && window_px % 2 == 1);
  cv::Mat image;
  gray.convertTo(image, CV_32F);
  const cv::Size box(window_px, window_px);
  cv::Mat mean, mean_sq;
  cv::boxFilter(image, mean, CV_32F, box, {-1, -1}, true, cv::BORDER_REFLECT);
  cv::sqrBoxFilter(image, mean_sq, CV_32F, box, {-1, -1}, true, cv::BORDER_REFLECT);
  cv::Mat variance = mean_sq - mean.mul(mean);
  cv::max(variance, 0.0, variance);
  cv::Mat sigma;
  cv::sqrt(variance, sigma);
  cv::Mat out;
  cv::divide(image - mean, sigma + epsilon, out);
  return out;
}

}  // namespace fleetloc::imaging
