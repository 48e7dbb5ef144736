// Masked NCC by FFT with the image's spectra kept (see masked_correlator.h).
#include "imaging/masked_correlator.h"

#include <opencv2/imgproc.hpp>

#include "base/status.h"

namespace fleetloc::imaging {
namespace {

// `values` zero-padded to `size` (top-left), transformed (CCS-packed).
cv::Mat Spectrum(const cv::Mat& values, cv::Size size) {
  cv::Mat padded = cv::Mat::zeros(size, CV_32F);
  values.copyTo(padded(cv::Rect(cv::Point(), values.size())));
  cv::Mat spectrum;
  cv::dft(padded, spectrum, 0, values.rows);
  return spectrum;
}

// Σ_u a(x + u) · b(u) for the placements x where b lies inside a, from their spectra.
cv::Mat Correlation(const cv::Mat& a_spectrum, const cv::Mat& b_spectrum, cv::Size valid) {
  cv::Mat product, out;
  cv::mulSpectrums(a_spectrum, b_spectrum, product, 0, true);
  cv::idft(product, out, cv::DFT_SCALE | cv::DFT_REAL_OUTPUT, valid.height);
  return out(cv::Rect(cv::Point(), valid));
}

}  // namespace

MaskedCorrelator::MaskedCorrelator(const cv::Mat& image) : image_size_(image.size()) {
  FLEETLOC_CHECK(image.type() == CV_32FC1 && !image.empty());
  dft_size_ = {cv::getOptimalDFTSize(image.cols), cv::getOptimalDFTSize(image.rows)};
  spectrum_ = Spectrum(image, dft_size_);
  spectrum_sq_ = Spectrum(image.mul(image), dft_size_);
}

void MaskedCorrelator::Match(const cv::Mat& templ, const cv::Mat& mask, cv::Mat* scores) const {
  FLEETLOC_CHECK(templ.type() == CV_32FC1 && mask.type() == CV_8UC1 &&
                 templ.size() == mask.size() && templ.cols <= image_size_.width &&
                 templ.rows <= image_size_.height);
  cv::Mat used, masked = cv::Mat::zeros(templ.size(), CV_32F);
  mask.convertTo(used, CV_32F, 1.0 / 255.0);
  cv::threshold(used, used, 0.0, 1.0, cv::THRESH_BINARY);
  templ.copyTo(masked, mask);
  const double templ_sq = masked.dot(masked);
  const cv::Size valid(image_size_.width - templ.cols + 1, image_size_.height - templ.rows + 1);
  const cv::Mat numerator = Correlation(spectrum_, Spectrum(masked, dft_size_), valid);
  cv::Mat image_sq = Correlation(spectrum_sq_, Spectrum(used, dft_size_), valid);
  cv::sqrt(cv::max(image_sq, 0.0) * templ_sq, image_sq);
  cv::divide(numerator, image_sq, *scores);
}

std::size_t MaskedCorrelator::MemoryBytes() const {
  return (spectrum_.total() + spectrum_sq_.total()) * sizeof(float);
}

}  // namespace fleetloc::imaging
