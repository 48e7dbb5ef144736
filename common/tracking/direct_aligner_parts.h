// The dense aligner's internals shared by its source files (direct_aligner.cpp: the cycle and
// its verdict; direct_levels.cpp: the frame pyramid and the Gauss–Newton levels; direct_search.cpp:
// the coarse search; direct_polish.cpp: the full-resolution polish). Not part of the interface.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <cstdint>
#include <opencv2/core.hpp>
#include <opencv2/core/hal/intrin.hpp>
#include <vector>

#include "geometry/camera_model.h"
#include "geometry/pose2.h"
#include "tracking/dense_linearization.h"
#include "tracking/direct_aligner.h"
#include "tracking/frame_mosaic_warp.h"

namespace fleetloc::tracking {
namespace direct_detail {

// One selected frame pixel: its level coordinates, normalized value, and its level-0 offset from
// the principal point (for the rotation column of the Jacobian), and its score block (the
// sandwich covariance's, kScoreBlocks² over the level).
struct PixelPoint {
  float u = 0, v = 0;
  float value = 0;
  float du0 = 0, dv0 = 0;
  std::uint8_t block = 0;
};

cv::Rect GrownBy(const cv::Rect& rect, int margin);
double Median(std::vector<float> values);
Eigen::Matrix3d RotationBlock(const geometry::Pose2& pose);
// pose ⊕ q⁻¹ with q in (level-0 px, px, rad).
geometry::Pose2 ApplyStep(const geometry::Pose2& pose, const Eigen::Vector3d& q_px,
                          double resolution_m);
// Largest 1-sigma displacement (level-0 px) over the frame corners under `covariance`.
double CornerSigmaPx(const geometry::CameraModel& camera, const geometry::PoseWithCovariance& pose);

}  // namespace direct_detail

// The normalized mosaic block a level reads, and how continuous mosaic coordinates index it.
struct DirectAligner::MosaicBlock {
  cv::Mat texels;  // CV_32FC4: value, d/dx, d/dy (central differences, per level pixel), 0
  cv::Rect rect;   // level pixels
  cv::Size level_size;

  // Bilinear value and gradient (out[0..2]; out[3] is scratch) at continuous level coordinates;
  // false outside the block or the mosaic. The channels are interpolated together from one
  // interleaved texel, a quarter of the memory traffic of three planes, in one 4-lane vector
  // where the CPU has them (OpenCV's universal intrinsics: SSE2 or NEON; the same arithmetic, in
  // the same order, as the scalar form).
  bool Sample(float x, float y, float out[4]) const {
    if (x < 0.5f || y < 0.5f || x > level_size.width - 0.5f || y > level_size.height - 0.5f) {
      return false;
    }
    const float bx = x - 0.5f - rect.x, by = y - 0.5f - rect.y;
    const int x0 = cvFloor(bx), y0 = cvFloor(by);
    if (x0 < 0 || y0 < 0 || x0 + 1 >= texels.cols || y0 + 1 >= texels.rows) return false;
    const float fx = bx - x0, fy = by - y0;
    const float* r0 = texels.ptr<float>(y0) + 4 * x0;
    const float* r1 = texels.ptr<float>(y0 + 1) + 4 * x0;
#if CV_SIMD128
    const cv::v_float32x4 a = cv::v_load(r0), b = cv::v_load(r0 + 4);
    const cv::v_float32x4 c = cv::v_load(r1), d = cv::v_load(r1 + 4);
    const cv::v_float32x4 wx = cv::v_setall_f32(fx);
    const cv::v_float32x4 top = a + wx * (b - a), bottom = c + wx * (d - c);
    cv::v_store(out, top + cv::v_setall_f32(fy) * (bottom - top));
#else
    for (int ch = 0; ch < 3; ++ch) {
      const float top = r0[ch] + fx * (r0[ch + 4] - r0[ch]);
      const float bottom = r1[ch] + fx * (r1[ch + 4] - r1[ch]);
      out[ch] = top + fy * (bottom - top);
    }
#endif
    return true;
  }
};

// The frame → view warp of one level at one pose, in float, and the residual's Jacobian there.
// The Jacobian takes the gradient of the warped mosaic (clean, noise-free) in frame axes rather
// than the frame's own: the noisy frame gradient overstates the curvature and makes the
// inverse-compositional steps too short (measured: linear convergence at ratio 0.75 on a plain
// floor; with the mosaic's gradient, 2–4 iterations per level).
struct DirectAligner::LevelWarp {
  LevelWarp(const FrameMosaicWarp& level_warp, int level)
      : linear(level_warp.linear.cast<float>()),
        to_frame(level_warp.linear.transpose().cast<float>()),
        offset(level_warp.offset.cast<float>()),
        scale(1.0f / static_cast<float>(1 << level)) {}

  // The view's value at `p` and the residual's Jacobian (before the contrast gain); false where
  // `p` falls outside the block or the mosaic.
  bool At(const MosaicBlock& source, const direct_detail::PixelPoint& p, float* value,
          Eigen::Vector3f* jacobian) const {
    const Eigen::Vector2f m = linear * Eigen::Vector2f(p.u, p.v) + offset;
    float sample[4];
    if (!source.Sample(m.x(), m.y(), sample)) return false;
    *value = sample[0];
    const Eigen::Vector2f g = to_frame * Eigen::Vector2f(sample[1], sample[2]);
    *jacobian = Eigen::Vector3f(-g.y() * scale, -g.x() * scale,
                                (g.x() * p.dv0 - g.y() * p.du0) * scale);
    return true;
  }

  Eigen::Matrix2f linear, to_frame;
  Eigen::Vector2f offset;
  float scale;
};

// The Tukey-weighted normal equations, correlation sums and per-block scores of a level's
// residuals t − gain·v. Summed per score block in float (a block holds at most a few hundred
// points, where float keeps six digits), then over the blocks in double.
class DirectAligner::WeightedSums {
 public:
  WeightedSums(double cutoff, double gain)
      : inverse_cutoff_(static_cast<float>(1.0 / cutoff)), gain_(static_cast<float>(gain)) {}

  // One point: its frame value t, the view's value v and the Jacobian before the gain.
  void Add(const direct_detail::PixelPoint& p, float v, const Eigen::Vector3f& jacobian) {
    ++points_;
    const float t = p.value, r = t - gain_ * v;
    const float x = r * inverse_cutoff_, x2 = x * x;
    if (x2 >= 1.0f) return;  // weight 0: adds nothing
    const float w = (1.0f - x2) * (1.0f - x2);
    Block& b = blocks_[p.block];
    b.sums[0] += w, b.sums[1] += w * t, b.sums[2] += w * v;
    b.sums[3] += w * t * t, b.sums[4] += w * v * v, b.sums[5] += w * t * v;
    const Eigen::Vector3f j = jacobian * gain_, wj = w * j;
    b.h[0] += wj.x() * j.x(), b.h[1] += wj.x() * j.y(), b.h[2] += wj.x() * j.z();
    b.h[3] += wj.y() * j.y(), b.h[4] += wj.y() * j.z(), b.h[5] += wj.z() * j.z();
    b.score += r * wj;
    ++b.count;
    b.inliers += w > 0.5f;
  }

  // The sums into `lin` (its h, g, correlation, next gain, inlier fraction, score spread, points).
  void Finish(Linearization* lin) const;

 private:
  struct Block {
    std::array<float, 6> sums{};  // Σw, Σw·t, Σw·v, Σw·t², Σw·v², Σw·t·v
    std::array<float, 6> h{};     // upper triangle of Σ w·J·Jᵀ
    Eigen::Vector3f score = Eigen::Vector3f::Zero();  // Σ w·r·J
    int count = 0, inliers = 0;
  };
  float inverse_cutoff_, gain_;
  int points_ = 0;
  std::array<Block, kScoreBlocks * kScoreBlocks> blocks_{};
};

struct DirectAligner::Level {
  int level = 0;
  cv::Mat normalized;  // CV_32F, the frame at this level, locally normalized
  cv::Mat searched;    // the same with occluders set to 0 (the floor's mean), for the search
  int border = 0;      // pixels whose normalization window was clipped
  std::vector<direct_detail::PixelPoint> points;
};

// The mosaic view at a level's points and the residuals' Jacobians (before the contrast gain);
// `valid` is 0 where a point falls outside the block or the mosaic.
struct DirectAligner::LevelSamples {
  std::vector<float> values;
  std::vector<Eigen::Vector3f> jacobians;
  std::vector<char> valid;
  double stv = 0.0, svv = 0.0;  // Σ frame·view and Σ view² over the valid points
};

}  // namespace fleetloc::tracking
