// The FFT correlators' transform length (see dft_size.h).
#include "imaging/dft_size.h"

namespace fleetloc::imaging {

int EvenDftSize(int n) {
  int size = cv::getOptimalDFTSize(n);
  while (size % 2 != 0) size = cv::getOptimalDFTSize(size + 1);
  return size;
}

cv::Size EvenDftSize(cv::Size size) { return {EvenDftSize(size.width), EvenDftSize(size.height)}; }

}  // namespace fleetloc::imaging
