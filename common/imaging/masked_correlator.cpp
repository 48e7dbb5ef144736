// Masked NCC by FFT with the image's spectrum kept (the mask's Σ M·I² from row prefix sums), and
// by direct sums at a few placements (see masked_correlator.h).
#include "imaging/masked_correlator.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "base/status.h"
#include "imaging/dft_size.h"
#include "imaging/simd.h"

namespace fleetloc::imaging {
namespace {

// `values` zero-padded to `size` (top-left), transformed (CCS-packed); what lies beyond `size`
// is left out (the caller knows it is zero).
cv::Mat Spectrum(const cv::Mat& values, cv::Size size) {
  const cv::Rect kept(0, 0, std::min(values.cols, size.width), std::min(values.rows, size.height));
  cv::Mat padded = cv::Mat::zeros(size, CV_32F);
  values(kept).copyTo(padded(kept));
  cv::Mat spectrum;
  cv::dft(padded, spectrum, 0, kept.height);
  return spectrum;
}

// The `size` block of `full` from `first`, indices taken modulo full's size (a cyclic
// correlation's output).
cv::Mat CyclicBlock(const cv::Mat& full, cv::Point first, cv::Size size) {
  first = {first.x % full.cols, first.y % full.rows};
  if (first.x + size.width <= full.cols && first.y + size.height <= full.rows)
    return full(cv::Rect(first, size));
  cv::Mat out(size, full.type());
  for (int y = 0; y < size.height;) {
    const int from_y = (first.y + y) % full.rows;
    const int rows = std::min(size.height - y, full.rows - from_y);
    for (int x = 0; x < size.width;) {
      const int from_x = (first.x + x) % full.cols;
      const int cols = std::min(size.width - x, full.cols - from_x);
      full(cv::Rect(from_x, from_y, cols, rows)).copyTo(out(cv::Rect(x, y, cols, rows)));
      x += cols;
    }
    y += rows;
  }
  return out;
}

// Σ_u a(x + u) · b(u) (`turned` false) or Σ_u a(x + u) · b(w − 1 − u) (true: b turned by π, w its
// size; a convolution read (w − 1) further) for the placements x where b lies inside a, from
// their spectra (b's size `b_size`).
cv::Mat Correlation(const cv::Mat& a_spectrum, const cv::Mat& b_spectrum, cv::Size b_size,
                    cv::Size valid, bool turned = false) {
  cv::Mat product, out;
  cv::mulSpectrums(a_spectrum, b_spectrum, product, 0, /*conjB=*/!turned);
  const cv::Point first = turned ? cv::Point(b_size.width - 1, b_size.height - 1) : cv::Point();
  // Only the rows read are needed, unless the read wraps around.
  const int rows = first.y + valid.height <= product.rows ? first.y + valid.height : 0;
  cv::idft(product, out, cv::DFT_SCALE | cv::DFT_REAL_OUTPUT, rows);
  return CyclicBlock(out, first, valid);
}

// A run of used mask pixels: row `row`, columns [begin, end).
struct Run {
  int row, begin, end;
};

// The mask's non-zero pixels as row runs (a rotated rectangle's: one run a row).
std::vector<Run> RunsOf(const cv::Mat& mask) {
  std::vector<Run> runs;
  for (int y = 0; y < mask.rows; ++y) {
    const uchar* row = mask.ptr<uchar>(y);
    for (int x = 0; x < mask.cols;) {
      if (row[x] == 0) {
        ++x;
        continue;
      }
      const int begin = x;
      while (x < mask.cols && row[x] != 0) ++x;
      runs.push_back({y, begin, x});
    }
  }
  return runs;
}

// Row prefix sums of I²: out(y, x) = Σ_{x' < x} I(y, x')², (W + 1) × H, summed in double.
cv::Mat RowPrefixSumsOfSquares(const cv::Mat& image) {
  cv::Mat sums(image.rows, image.cols + 1, CV_32F);
  for (int y = 0; y < image.rows; ++y) {
    const float* in = image.ptr<float>(y);
    float* out = sums.ptr<float>(y);
    double running = 0;
    out[0] = 0;
    for (int x = 0; x < image.cols; ++x) {
      running += static_cast<double>(in[x]) * in[x];
      out[x + 1] = static_cast<float>(running);
    }
  }
  return sums;
}

// out[x] += ends[x] − begins[x]: one run's sums added at a row of placements.
FLEETLOC_VECTOR_CLONES
void AddRunSums(const float* ends, const float* begins, int n, float* out) {
  for (int x = 0; x < n; ++x) out[x] += ends[x] - begins[x];
}

// Σ M·I² at every placement in `valid`: per run of the mask, the difference of two shifted
// views of the row prefix sums (no transform), a row of placements at a time so that the row
// stays in cache while every run is added (the whole map once per run was 20 % of the fine
// dense search's sweep at 1280×1024; the same sums in the same order).
cv::Mat MaskedEnergy(const cv::Mat& row_sums_sq, const cv::Mat& mask, cv::Size valid) {
  const std::vector<Run> runs = RunsOf(mask);
  cv::Mat energy = cv::Mat::zeros(valid, CV_32F);
  for (int y = 0; y < valid.height; ++y) {
    float* out = energy.ptr<float>(y);
    for (const Run& r : runs) {
      const float* sums = row_sums_sq.ptr<float>(y + r.row);
      AddRunSums(sums + r.end, sums + r.begin, valid.width, out);
    }
  }
  return energy;
}

// numerator / sqrt(image_sq · templ_sq), image_sq clamped at 0.
void Normalized(const cv::Mat& numerator, const cv::Mat& image_sq, double templ_sq,
                cv::Mat* scores) {
  cv::Mat denominator;
  cv::sqrt(cv::max(image_sq, 0.0) * templ_sq, denominator);
  cv::divide(numerator, denominator, *scores);
}

// The template with its unused pixels zeroed, and Σ (T·M)².
struct Prepared {
  cv::Mat masked;
  double templ_sq = 0;
};

Prepared Prepare(const cv::Mat& templ, const cv::Mat& mask, cv::Size image_size) {
  FLEETLOC_CHECK(templ.type() == CV_32FC1 && mask.type() == CV_8UC1 &&
                 templ.size() == mask.size() && templ.cols <= image_size.width &&
                 templ.rows <= image_size.height);
  Prepared p;
  p.masked = cv::Mat::zeros(templ.size(), CV_32F);
  templ.copyTo(p.masked, mask);
  p.templ_sq = p.masked.dot(p.masked);
  return p;
}

// Placements of a template inside an image.
cv::Size ValidSize(cv::Size image, cv::Size templ) {
  return {image.width - templ.width + 1, image.height - templ.height + 1};
}

// Whether `image` is zero within `border` pixels of each side.
bool ZeroBorder(const cv::Mat& image, int border) {
  if (border == 0) return true;
  const cv::Rect inner(border, border, image.cols - 2 * border, image.rows - 2 * border);
  cv::Mat outside = image != 0;
  outside(inner).setTo(0);
  return cv::countNonZero(outside) == 0;
}

}  // namespace

MaskedCorrelator::MaskedCorrelator(const cv::Mat& image, int zero_border_px)
    : image_size_(image.size()), zero_border_px_(zero_border_px) {
  FLEETLOC_CHECK(image.type() == CV_32FC1 && !image.empty() && zero_border_px >= 0 &&
                 2 * zero_border_px < std::min(image.cols, image.rows) &&
                 ZeroBorder(image, zero_border_px));
  // A cyclic correlation of this length reads, past the image's end, only the zero border at
  // its start (and the image's own end is zero as far as it is left out).
  dft_size_ = EvenDftSize({image.cols - zero_border_px, image.rows - zero_border_px});
  spectrum_ = Spectrum(image, dft_size_);
  row_sums_sq_ = RowPrefixSumsOfSquares(image);
}

void MaskedCorrelator::CheckLargerThanZeroBorder(const cv::Mat& templ) const {
  // Then every placement has its own cell of the cyclic output.
  FLEETLOC_CHECK(templ.cols > zero_border_px_ && templ.rows > zero_border_px_);
}

void MaskedCorrelator::Match(const cv::Mat& templ, const cv::Mat& mask, cv::Mat* scores) const {
  CheckLargerThanZeroBorder(templ);
  const Prepared p = Prepare(templ, mask, image_size_);
  const cv::Size valid = ValidSize(image_size_, templ.size());
  const cv::Size size = templ.size();
  Normalized(Correlation(spectrum_, Spectrum(p.masked, dft_size_), size, valid),
             MaskedEnergy(row_sums_sq_, mask, valid), p.templ_sq, scores);
}

void MaskedCorrelator::MatchWithTurned(const cv::Mat& templ, const cv::Mat& mask, cv::Mat* scores,
                                       cv::Mat* turned_scores) const {
  CheckLargerThanZeroBorder(templ);
  const Prepared p = Prepare(templ, mask, image_size_);
  const cv::Size valid = ValidSize(image_size_, templ.size());
  const cv::Size size = templ.size();
  const cv::Mat templ_spectrum = Spectrum(p.masked, dft_size_);
  const cv::Mat image_sq = MaskedEnergy(row_sums_sq_, mask, valid);
  cv::Mat turned_mask;
  cv::flip(mask, turned_mask, -1);
  // Σ M·I² is the same for a mask its turn leaves unchanged.
  const bool symmetric = cv::countNonZero(turned_mask != mask) == 0;
  const cv::Mat turned_image_sq =
      symmetric ? image_sq : MaskedEnergy(row_sums_sq_, turned_mask, valid);
  Normalized(Correlation(spectrum_, templ_spectrum, size, valid), image_sq, p.templ_sq, scores);
  Normalized(Correlation(spectrum_, templ_spectrum, size, valid, /*turned=*/true), turned_image_sq,
             p.templ_sq, turned_scores);
}

std::size_t MaskedCorrelator::MemoryBytes() const {
  return (spectrum_.total() + row_sums_sq_.total()) * sizeof(float);
}

void MatchAtFewPlacements(const cv::Mat& image, const cv::Mat& templ, const cv::Mat& mask,
                          cv::Mat* scores) {
  FLEETLOC_CHECK(image.type() == CV_32FC1);
  const Prepared p = Prepare(templ, mask, image.size());
  const cv::Size valid = ValidSize(image.size(), templ.size());
  const cv::Mat image_energy = MaskedEnergy(RowPrefixSumsOfSquares(image), mask, valid);
  scores->create(valid, CV_32F);
  // Hand-written over the placements (each numerator a library dot product): the transforms of
  // cv::matchTemplate cost twice the instructions for the dense search's refinement (callgrind).
  for (int y = 0; y < scores->rows; ++y) {
    for (int x = 0; x < scores->cols; ++x) {
      const double numerator = p.masked.dot(image(cv::Rect(cv::Point(x, y), templ.size())));
      const double energy = std::max(static_cast<double>(image_energy.at<float>(y, x)), 0.0);
      scores->at<float>(y, x) = static_cast<float>(numerator / std::sqrt(energy * p.templ_sq));
    }
  }
}

}  // namespace fleetloc::imaging
