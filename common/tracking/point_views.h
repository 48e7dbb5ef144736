// The mosaic view sampled at a dense level's chosen pixels: what each Gauss–Newton iteration of
// the dense alignment reads (DirectAligner::LevelWarp). Eight pixels at a time with AVX2 where the
// CPU has it, the same floats as the scalar loop.
#pragma once

#include <opencv2/core.hpp>

#include "tracking/dense_linearization.h"

namespace fleetloc::tracking {

// A level's frame → view warp in float: level pixel (u, v) ↦ linear·(u, v) + offset in the
// level's mosaic pixels; to_frame takes a mosaic gradient to frame axes, and scale to level-0 px.
struct PointWarp {
  float linear[2][2];
  float offset[2];
  float to_frame[2][2];
  float scale;
};

// The normalized mosaic under a level: texels (CV_32FC4, continuous: value, d/dx, d/dy, 0) of
// the level's block starting at `origin` (level px), in a level of `level_size`.
struct TexelBlock {
  const cv::Mat* texels;
  cv::Point origin;
  cv::Size level_size;
};

// Which loop samples: the fastest the CPU has, or the scalar one (tests and benchmarks compare).
enum class SamplingPath { kFastest, kScalar };

// The view at every pixel of `points` into `views` (resized to them): bilinear at continuous level
// coordinates, and unseen (all four arrays 0) outside the block or the mosaic.
void SamplePointViews(const PointWarp& warp, const TexelBlock& block, const PointSet& points,
                      PointViews* views, SamplingPath path = SamplingPath::kFastest);

}  // namespace fleetloc::tracking
