// Pose refinement (paper 000 §2.8): a Kalman update of the camera pose (x, y, theta) in map with
// all template correspondences as measurements, iterated to convergence, removing the
// correspondence whose residual is markedly above the rest and repeating.
#pragma once

#include <vector>

#include "geometry/pose2.h"

namespace fleetloc::tracking {

// One template match: the template centre in camera_ground (metres) and where it was observed in
// map (metres), with the observation's 1-sigma (metres, isotropic).
struct Correspondence {
  Eigen::Vector2d ground;
  Eigen::Vector2d observed;
  double sigma_m = 1e-4;
};

struct OutlierOptions {
  double ratio = 3.0;            // reject max residual > ratio × median of the others …
  double min_residual_m = 3e-4;  // … and > this
  int min_inliers = 3;           // never go below this many
};

struct PoseUpdate {
  geometry::PoseWithCovariance posterior;
  std::vector<bool> inlier;  // per correspondence
  int inliers = 0;
  double rms_residual_m = 0.0;  // over inliers, after the update
};

// Iterated EKF update in information form (3×3 solves only). `prior` must have a positive
// definite covariance. With fewer than 2 correspondences the posterior equals the prior and no
// correspondence is an inlier.
PoseUpdate KalmanPoseUpdate(const geometry::PoseWithCovariance& prior,
                            const std::vector<Correspondence>& matches,
                            const OutlierOptions& options);

}  // namespace fleetloc::tracking
