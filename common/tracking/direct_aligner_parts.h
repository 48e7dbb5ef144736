// The dense aligner's internals shared by its source files (direct_aligner.cpp: the cycle and
// its verdict; direct_levels.cpp: the frame pyramid and the Gauss–Newton levels; direct_search.cpp:
// the coarse search; direct_polish.cpp: the full-resolution polish). Not part of the interface.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <opencv2/core.hpp>
#include <vector>

#include "geometry/camera_model.h"
#include "geometry/pose2.h"
#include "tracking/direct_aligner.h"

namespace fleetloc::tracking {
namespace direct_detail {

// One selected frame pixel: its level coordinates, normalized value, and its level-0 offset from
// the principal point (for the rotation column of the Jacobian).
struct PixelPoint {
  float u = 0, v = 0;
  float value = 0;
  float du0 = 0, dv0 = 0;
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

  // Bilinear value and gradient (out[0..2]) at continuous level coordinates; false outside the
  // block or the mosaic. The three channels are interpolated together from one interleaved
  // texel, a quarter of the memory traffic of three planes.
  bool Sample(float x, float y, float out[3]) const {
    if (x < 0.5f || y < 0.5f || x > level_size.width - 0.5f || y > level_size.height - 0.5f) {
      return false;
    }
    const float bx = x - 0.5f - rect.x, by = y - 0.5f - rect.y;
    const int x0 = static_cast<int>(std::floor(bx)), y0 = static_cast<int>(std::floor(by));
    if (x0 < 0 || y0 < 0 || x0 + 1 >= texels.cols || y0 + 1 >= texels.rows) return false;
    const float fx = bx - x0, fy = by - y0;
    const float* r0 = texels.ptr<float>(y0) + 4 * x0;
    const float* r1 = texels.ptr<float>(y0 + 1) + 4 * x0;
    for (int c = 0; c < 3; ++c) {
      const float top = r0[c] + fx * (r0[c + 4] - r0[c]);
      const float bottom = r1[c] + fx * (r1[c + 4] - r1[c]);
      out[c] = top + fy * (bottom - top);
    }
    return true;
  }
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
