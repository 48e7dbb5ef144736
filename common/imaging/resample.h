// Bilinear affine resampling for the tracker's views: of an image (8-bit or float), and of the
// means of an 8-bit image's 2 × 2 squares without materializing them (a frame level's view of the
// mosaic, see tracking/predicted_view.h). Written by hand rather than calling cv::warpAffine,
// which interpolates with 5-bit fixed-point weights and rounds to the source's type, and costs
// 19 µs on a 48² patch (this Debian build, one core) where these loops take a few.
#pragma once

#include <opencv2/core.hpp>

namespace fleetloc::imaging {

// dst(i, j) = bilinear src at dst_to_src · (j, i, 1) (pixel-index coordinates, as
// cv::warpAffine with WARP_INVERSE_MAP); 0 outside src. src CV_8UC1 or CV_32FC1; returns CV_32F.
cv::Mat ResampleAffine(const cv::Mat& src, const cv::Matx23d& dst_to_src, cv::Size size);

// ResampleAffine of BoxAverage(src, 2), the same floats, without computing the means that are not
// sampled: src CV_8UC1; dst_to_src maps into the means' image ((rows − 1) × (cols − 1), mean
// (y, x) over src rows y, y + 1 and columns x, x + 1); 0 outside it.
cv::Mat ResamplePairMeans(const cv::Mat& src, const cv::Matx23d& dst_to_src, cv::Size size);

// The mean of each k × k square of an 8-bit image (k a power of two), at the square's top-left
// pixel: CV_32F of (rows − k + 1) × (cols − k + 1), exact (sums of at most 2^16 bytes scaled by a
// power of two). cv::boxFilter gives the same numbers at 12 instructions a pixel (this Debian
// build, 8-bit to float, k = 2) and 18 through 16-bit sums.
cv::Mat BoxAverage(const cv::Mat& image, int k);

}  // namespace fleetloc::imaging
