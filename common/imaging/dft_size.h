// The transform length the FFT-based correlators pad to: OpenCV's fastest lengths, even.
#pragma once

#include <opencv2/core.hpp>

namespace fleetloc::imaging {

// The smallest even length >= n that cv::getOptimalDFTSize accepts (a product of 2, 3 and 5).
// getOptimalDFTSize alone may return an odd length (375, 625, 675, 729), at which OpenCV 4.6's
// real transform takes 1.5–1.9 times as long per pixel as at an even one: measured on one core
// here, 625×400 2.24 ms against 640×400 1.40 ms, 375×400 1.31 ms against 384×400 0.82 ms
// (docs/benchmarks.md, issue 17, session 50).
int EvenDftSize(int n);
cv::Size EvenDftSize(cv::Size size);

}  // namespace fleetloc::imaging
