// The dense aligner's internals shared by its source files (direct_aligner.cpp: the cycle and
// its verdict; direct_levels.cpp: the frame pyramid and the Gauss–Newton levels; direct_search.cpp:
// the coarse search; direct_polish.cpp: the full-resolution polish). Not part of the interface.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cmath>
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

  // Bilinear value and gradient (out[0..2]; out[3] is scratch) between the texels at r0, r0 + 4
  // (top row) and r1, r1 + 4 (bottom row), at fractions fx, fy. The channels are interpolated
  // together from one interleaved texel, a quarter of the memory traffic of three planes, in one
  // 4-lane vector where the CPU has them (OpenCV's universal intrinsics: SSE2 or NEON; the same
  // arithmetic, in the same order, as the scalar form).
  static void Bilinear(const float* r0, const float* r1, float fx, float fy, float out[4]) {
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
  }
};

// The frame → view warp of one level at one pose, in float, and the view it gives a level's pixels.
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

  // The view at every pixel of `points`: bilinear at continuous level coordinates, unseen outside
  // the block or the mosaic (the bounds as floats once, out of the loop).
  PointViews Views(const MosaicBlock& source, const PointSet& points) const {
    PointViews views(points.size());
    const float max_x = source.level_size.width - 0.5f, max_y = source.level_size.height - 0.5f;
    const float origin_x = static_cast<float>(source.rect.x);
    const float origin_y = static_cast<float>(source.rect.y);
    const int last_x0 = source.texels.cols - 2, last_y0 = source.texels.rows - 2;
    for (size_t i = 0; i < points.size(); ++i) {
      const Eigen::Vector2f m = linear * Eigen::Vector2f(points.u[i], points.v[i]) + offset;
      if (!(m.x() >= 0.5f && m.y() >= 0.5f && m.x() <= max_x && m.y() <= max_y)) continue;
      const float bx = m.x() - 0.5f - origin_x, by = m.y() - 0.5f - origin_y;
      if (!(bx >= 0.0f && by >= 0.0f)) continue;
      const int x0 = static_cast<int>(bx), y0 = static_cast<int>(by);  // the floor, as bx, by ≥ 0
      if (x0 > last_x0 || y0 > last_y0) continue;
      float sample[4];
      MosaicBlock::Bilinear(source.texels.ptr<float>(y0) + 4 * x0,
                            source.texels.ptr<float>(y0 + 1) + 4 * x0, bx - x0, by - y0, sample);
      const Eigen::Vector2f g = to_frame * Eigen::Vector2f(sample[1], sample[2]);
      views.value[i] = sample[0];
      views.gx[i] = g.x() * scale;
      views.gy[i] = g.y() * scale;
      views.seen[i] = 1.0f;
    }
    return views;
  }

  Eigen::Matrix2f linear, to_frame;
  Eigen::Vector2f offset;
  float scale;
};

struct DirectAligner::Level {
  int level = 0;
  cv::Mat normalized;  // CV_32F, the frame at this level, locally normalized
  cv::Mat searched;    // the same with occluders set to 0 (the floor's mean), for the search
  int border = 0;      // pixels whose normalization window was clipped
  PointSet points;     // grouped by score block
};

}  // namespace fleetloc::tracking
