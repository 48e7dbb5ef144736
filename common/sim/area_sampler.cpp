// Area-sensor sampling with per-frame tabulated weights.
#include "sim/area_sampler.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <opencv2/core/hal/intrin.hpp>
#include <opencv2/core/utility.hpp>

#include "base/status.h"

namespace fleetloc::sim {
namespace {

constexpr int kMaxTaps = 32;  // a pixel covering up to ~28 source pixels across (table size)

// Row s · phases + p: the bilinear weights over taps first_tap .. first_tap + taps - 1 of the
// sub-pixel sample s (at `offsets`[s] from the pixel centre) when the centre has phase
// (p + 0.5) / phases.
Eigen::MatrixXd AxisWeights(const std::vector<double>& offsets, int phases, int first_tap,
                            int taps) {
  Eigen::MatrixXd weights = Eigen::MatrixXd::Zero(offsets.size() * phases, taps);
  for (size_t s = 0; s < offsets.size(); ++s) {
    for (int p = 0; p < phases; ++p) {
      const double x = (p + 0.5) / phases + offsets[s];
      const double base = std::floor(x);
      const int tap = static_cast<int>(base) - first_tap;
      weights(s * phases + p, tap) = 1.0 - (x - base);
      weights(s * phases + p, tap + 1) = x - base;
    }
  }
  return weights;
}

}  // namespace

AreaSampler::AreaSampler(const Eigen::Matrix<double, 2, 3>& pixel_to_source, int supersample) {
  FLEETLOC_CHECK(supersample >= 1);
  to_index_ = pixel_to_source;
  to_index_.col(2) -= Eigen::Vector2d(0.5, 0.5);  // continuous → index (pixel centres)
  // Offsets of the k × k sub-pixel points from the pixel centre, in source pixels, per axis.
  std::vector<double> offset_x, offset_y;
  for (int b = 0; b < supersample; ++b) {
    for (int a = 0; a < supersample; ++a) {
      const Eigen::Vector2d d =
          pixel_to_source.leftCols<2>() *
          Eigen::Vector2d((a + 0.5) / supersample - 0.5, (b + 0.5) / supersample - 0.5);
      offset_x.push_back(d.x());
      offset_y.push_back(d.y());
    }
  }
  const auto [min_x, max_x] = std::minmax_element(offset_x.begin(), offset_x.end());
  const auto [min_y, max_y] = std::minmax_element(offset_y.begin(), offset_y.end());
  first_tap_ = static_cast<int>(std::floor(std::min(*min_x, *min_y)));
  taps_ = static_cast<int>(std::ceil(std::max(*max_x, *max_y))) + 1 - first_tap_ + 1;
  FLEETLOC_CHECK(taps_ <= kMaxTaps);
  const Eigen::MatrixXd wx = AxisWeights(offset_x, kPhases, first_tap_, taps_);
  const Eigen::MatrixXd wy = AxisWeights(offset_y, kPhases, first_tap_, taps_);
  const int samples = supersample * supersample;
  weights_.resize(static_cast<size_t>(kPhases * kPhases * taps_ * taps_));
  Eigen::MatrixXd sub_x(samples, taps_), sub_y(samples, taps_);
  for (int py = 0; py < kPhases; ++py) {
    for (int s = 0; s < samples; ++s) sub_y.row(s) = wy.row(s * kPhases + py);
    for (int px = 0; px < kPhases; ++px) {
      for (int s = 0; s < samples; ++s) sub_x.row(s) = wx.row(s * kPhases + px);
      // Σ over samples of (y weights) ⊗ (x weights) / samples, stored row-major (tap_y, tap_x).
      const Eigen::MatrixXd w = sub_y.transpose() * sub_x / samples;
      float* out = &weights_[static_cast<size_t>((py * kPhases + px) * taps_ * taps_)];
      for (int r = 0; r < taps_; ++r) {
        for (int c = 0; c < taps_; ++c) out[r * taps_ + c] = static_cast<float>(w(r, c));
      }
    }
  }
}

cv::Rect AreaSampler::SourceRect(cv::Size size) const {
  Eigen::Vector2d lo(INFINITY, INFINITY), hi(-INFINITY, -INFINITY);
  for (const Eigen::Vector2d& p :
       {Eigen::Vector2d(0.5, 0.5), Eigen::Vector2d(size.width - 0.5, 0.5),
        Eigen::Vector2d(0.5, size.height - 0.5),
        Eigen::Vector2d(size.width - 0.5, size.height - 0.5)}) {
    const Eigen::Vector2d x = to_index_ * p.homogeneous();
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  // One pixel of slack on each side for rounding in the incremental coordinates.
  const cv::Point tl(static_cast<int>(std::floor(lo.x())) + first_tap_ - 1,
                     static_cast<int>(std::floor(lo.y())) + first_tap_ - 1);
  const cv::Point br(static_cast<int>(std::floor(hi.x())) + first_tap_ + taps_ + 1,
                     static_cast<int>(std::floor(hi.y())) + first_tap_ + taps_ + 1);
  return {tl, br};
}

namespace {

// The taps × taps weighted sum of the source pixels from `s` on (rows `stride` bytes apart).
inline float WeightedSum(const std::uint8_t* s, size_t stride, const float* w, int taps) {
#if CV_SIMD128
  if (taps == 4) {  // the usual case (supersampling at equal resolutions): one vector per row
    cv::v_float32x4 sum = cv::v_setzero_f32();
    for (int r = 0; r < 4; ++r, s += stride) {
      const cv::v_float32x4 pixels =
          cv::v_cvt_f32(cv::v_reinterpret_as_s32(cv::v_load_expand_q(s)));
      sum = cv::v_muladd(pixels, cv::v_load(w + 4 * r), sum);
    }
    return cv::v_reduce_sum(sum);
  }
#endif
  float sum = 0.0f;
  for (int r = 0; r < taps; ++r, s += stride) {
    for (int c = 0; c < taps; ++c) sum += w[r * taps + c] * static_cast<float>(s[c]);
  }
  return sum;
}

}  // namespace

cv::Mat AreaSampler::Sample(const cv::Mat& source, const cv::Rect& source_rect,
                            cv::Size size) const {
  FLEETLOC_CHECK(source.type() == CV_8UC1 && source.size() == source_rect.size());
  FLEETLOC_CHECK((SourceRect(size) & source_rect) == SourceRect(size));
  cv::Mat out(size, CV_32FC1);
  // Fixed-point index coordinates relative to the block (never negative): the integer part
  // addresses the taps, the top fraction bits are the phase; 2^-24 px steps drift < 1e-4 px per
  // row.
  constexpr int kFractionBits = 24;
  constexpr int kPhaseShift = kFractionBits - kPhaseBits;
  const double one = static_cast<double>(std::int64_t{1} << kFractionBits);
  const std::int64_t step_x = std::llround(to_index_(0, 0) * one);
  const std::int64_t step_y = std::llround(to_index_(1, 0) * one);
  cv::parallel_for_(cv::Range(0, size.height), [&](const cv::Range& rows) {
    for (int j = rows.start; j < rows.end; ++j) {
      const Eigen::Vector2d start = to_index_ * Eigen::Vector3d(0.5, j + 0.5, 1.0) -
                                    Eigen::Vector2d(source_rect.x, source_rect.y);
      std::int64_t x = std::llround(start.x() * one), y = std::llround(start.y() * one);
      auto* row = out.ptr<float>(j);
      for (int i = 0; i < size.width; ++i, x += step_x, y += step_y) {
        const auto ix = static_cast<int>(x >> kFractionBits);
        const auto iy = static_cast<int>(y >> kFractionBits);
        const auto px = static_cast<int>(x >> kPhaseShift) & (kPhases - 1);
        const auto py = static_cast<int>(y >> kPhaseShift) & (kPhases - 1);
        row[i] =
            WeightedSum(source.ptr<std::uint8_t>(iy + first_tap_) + ix + first_tap_, source.step[0],
                        &weights_[static_cast<size_t>((py * kPhases + px) * taps_ * taps_)], taps_);
      }
    }
  });
  return out;
}

}  // namespace fleetloc::sim
