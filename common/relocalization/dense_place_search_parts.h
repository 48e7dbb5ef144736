// The dense place search's internals shared by its source files (dense_place_search.cpp: the
// normalized levels and the heading sweep; dense_place_search_refine.cpp: the refinement one level
// finer, the distinct alternative, the distinct best). Not part of the interface.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <memory>
#include <opencv2/core.hpp>

#include "geometry/camera_model.h"
#include "geometry/pose2.h"
#include "imaging/masked_correlator.h"
#include "relocalization/dense_place_search.h"

namespace fleetloc::relocalization {

// The whole mosaic at one pyramid level, normalized, with its geotransform.
struct DensePlaceSearch::Level {
  int level = 0;
  cv::Mat normalized;  // CV_32F
  geometry::Geotransform geo;
  double half_diagonal_px = 0;  // of a frame at this level
  int pad_px = 0;               // zero border around the mosaic
  double heading_step_rad = 0;
  std::unique_ptr<imaging::MaskedCorrelator> correlator;  // of `normalized`: its spectra kept
};

// The normalized frame rotated into the mosaic's axes for heading θ: the template, its mask, and
// the template's continuous coordinates of the frame centre.
struct Template {
  cv::Mat pixels, mask;
  Eigen::Vector2d centre;
};

// (I − μ) / (σ + ε) over a window, clipped to ±clip; CV_32F.
cv::Mat NormalizeClipped(const cv::Mat& image, int window, double clip);
// Frame pixel directions → mosaic pixel directions at the same level, for heading θ.
Eigen::Matrix2d FrameToMosaic(const geometry::CameraModel& camera,
                              const geometry::Geotransform& geo, double theta);
Template RotatedFrame(const cv::Mat& frame, const Eigen::Matrix2d& l);
// Places where the template meets only the zero border (0 / 0) score 0, not NaN or infinity.
void FiniteScores(cv::Mat* scores);
// body(i) for every i in [0, n), on up to `threads` stripes of OpenCV's pool; body(i) may write
// only what belongs to i.
void InParallel(int n, int threads, const std::function<void(int)>& body);
// The camera pose whose frame centre lands at mosaic continuous coordinates `at` (of `level`).
geometry::Pose2 PoseAt(const geometry::CameraModel& camera, const geometry::Geotransform& geo,
                       const Eigen::Vector2d& at, double theta);

}  // namespace fleetloc::relocalization
