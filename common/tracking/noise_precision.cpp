// Residual precision from a per-frame noise fit (see noise_precision.h).
#include "tracking/noise_precision.h"

#include <algorithm>
#include <cmath>

#include "imaging/simd.h"
#include "tracking/dense_linearization.h"

namespace fleetloc::tracking {

namespace {

constexpr int kGridStep = 4;  // every 4th pixel of every 4th row: ~19,000 samples at 640×480
constexpr int kBins = 5;
constexpr size_t kMinSamples = 500;
// The median of a χ²₁ variable is 0.4549 times its mean: a bin's median squared residual over
// this is its variance, robust to the occluders among its pixels.
constexpr double kChiSquare1Median = 0.4549;

struct Sample {
  float u, r2;
};

// The grid's frame value, view value and local variance.
template <typename Visit>
void VisitGrid(const cv::Mat& frame, const cv::Mat& view, const cv::Rect& inner,
               const std::vector<cv::Range>& spans, const cv::Mat& local_variance, Visit visit) {
  for (int y = 0; y < inner.height; y += kGridStep) {
    const float* t = frame.ptr<float>(inner.y + y) + inner.x;
    const float* uu = local_variance.ptr<float>(inner.y + y) + inner.x;
    const float* v = view.ptr<float>(y + 1) + 1;
    const int start = spans.empty() ? 0 : spans[y].start;
    const int end = spans.empty() ? inner.width : spans[y].end;
    for (int x = start; x < end; x += kGridStep) visit(t[x], v[x], uu[x]);
  }
}

// The samples' u and squared residual against the view at its least-squares contrast.
std::vector<Sample> ResidualSamples(const cv::Mat& frame, const cv::Mat& view,
                                    const cv::Rect& inner, const std::vector<cv::Range>& spans,
                                    const cv::Mat& local_variance, float epsilon) {
  double stv = 0, svv = 0;
  VisitGrid(frame, view, inner, spans, local_variance, [&](float t, float v, float) {
    stv += t * v;
    svv += v * v;
  });
  const float gain = static_cast<float>(LeastSquaresGain(stv, svv));
  std::vector<Sample> samples;
  samples.reserve((inner.width / kGridStep + 1) * (inner.height / kGridStep + 1));
  VisitGrid(frame, view, inner, spans, local_variance, [&](float t, float v, float variance) {
    const float r = t - gain * v;
    samples.push_back({NormalizationFactorSquared(variance, epsilon), r * r});
  });
  return samples;
}

// Splits `samples` in place into kBins runs of ascending u (each run's u below the next's) and
// returns each run's median u and variance (median r² / kChiSquare1Median).
void BinByU(std::vector<Sample>* samples, std::vector<double>* u, std::vector<double>* variance) {
  const auto by_u = [](const Sample& a, const Sample& b) { return a.u < b.u; };
  const auto by_r2 = [](const Sample& a, const Sample& b) { return a.r2 < b.r2; };
  const size_t n = samples->size();
  for (int b = 0; b < kBins; ++b) {
    const auto lo = samples->begin() + n * b / kBins, hi = samples->begin() + n * (b + 1) / kBins;
    if (hi != samples->end()) std::nth_element(lo, hi, samples->end(), by_u);
    const auto mid = lo + (hi - lo) / 2;
    std::nth_element(lo, mid, hi, by_u);
    u->push_back(mid->u);
    std::nth_element(lo, mid, hi, by_r2);
    variance->push_back(mid->r2 / kChiSquare1Median);
  }
}

}  // namespace

ResidualNoise FitResidualNoise(const cv::Mat& frame, const cv::Mat& view, const cv::Rect& inner,
                               const std::vector<cv::Range>& spans, const cv::Mat& local_variance,
                               float epsilon) {
  CV_Assert(frame.type() == CV_32F && view.type() == CV_32F && local_variance.type() == CV_32F);
  CV_Assert(local_variance.size() == frame.size());
  CV_Assert(view.cols == inner.width + 2 && view.rows == inner.height + 2);
  std::vector<Sample> samples = ResidualSamples(frame, view, inner, spans, local_variance, epsilon);
  ResidualNoise noise;
  if (samples.size() < kMinSamples) return noise;
  std::vector<double> bin_u, bin_variance;
  BinByU(&samples, &bin_u, &bin_variance);
  double mean_u = 0, mean_variance = 0;
  for (int b = 0; b < kBins; ++b) {
    mean_u += bin_u[b] / kBins;
    mean_variance += bin_variance[b] / kBins;
  }
  double suu = 0, suv = 0;
  for (int b = 0; b < kBins; ++b) {
    suu += (bin_u[b] - mean_u) * (bin_u[b] - mean_u);
    suv += (bin_u[b] - mean_u) * (bin_variance[b] - mean_variance);
  }
  noise.b = suu > 0 ? std::max(0.0, suv / suu) : 0.0;
  noise.a = std::max(mean_variance - noise.b * mean_u, 0.1 * bin_variance[0]);
  noise.median_u = bin_u[kBins / 2];
  return noise;
}

namespace {

// c / (1 + k·u(x)) over a row, with u the normalization factor squared: c·d² / (d² + k), d the
// pixel's spread plus epsilon. One loop the compiler vectorizes (0.36 M instructions a 320×240
// level scalar, measured in session 48).
FLEETLOC_VECTOR_CLONES void PrecisionRow(const float* local_variance, int n, float c, float k,
                                         float epsilon, float* out) {
  for (int x = 0; x < n; ++x) {
    const float d = std::sqrt(std::max(local_variance[x], 0.0f)) + epsilon;
    const float d2 = d * d;
    out[x] = c * d2 / (d2 + k);
  }
}

}  // namespace

cv::Mat ResidualPrecision(const ResidualNoise& noise, const cv::Mat& local_variance,
                          float epsilon) {
  if (!(noise.b > 0) || !(noise.a > 0)) return cv::Mat();
  // (A + B·ū)/(A + B·u) = c / (1 + k·u) with k = B/A, c = 1 + k·ū.
  const float k = static_cast<float>(noise.b / noise.a);
  const float c = static_cast<float>(1.0 + noise.b / noise.a * noise.median_u);
  cv::Mat precision(local_variance.size(), CV_32F);
  for (int y = 0; y < precision.rows; ++y) {
    PrecisionRow(local_variance.ptr<float>(y), precision.cols, c, k, epsilon,
                 precision.ptr<float>(y));
  }
  return precision;
}

}  // namespace fleetloc::tracking
