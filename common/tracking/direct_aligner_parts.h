// The dense aligner's internals shared by its source files (direct_aligner.cpp: the cycle and
// its verdict; direct_levels.cpp: the frame pyramid and the Gauss–Newton levels; direct_search.cpp:
// the coarse search; direct_polish.cpp: the full-resolution polish). Not part of the interface.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <opencv2/core.hpp>
#include <vector>

#include "geometry/camera_model.h"
#include "geometry/pose2.h"
#include "tracking/dense_linearization.h"
#include "tracking/direct_aligner.h"
#include "tracking/frame_mosaic_warp.h"
#include "tracking/point_views.h"

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

  // The view at every pixel of `points` into `views` (SamplePointViews; a level's iterations
  // reuse one set of arrays).
  void Views(const MosaicBlock& source, const PointSet& points, PointViews* views) const {
    const PointWarp warp{{{linear(0, 0), linear(0, 1)}, {linear(1, 0), linear(1, 1)}},
                         {offset.x(), offset.y()},
                         {{to_frame(0, 0), to_frame(0, 1)}, {to_frame(1, 0), to_frame(1, 1)}},
                         scale};
    SamplePointViews(warp, TexelBlock{&source.texels, source.rect.tl(), source.level_size}, points,
                     views);
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
