// A correspondence-free RANSAC map fit, the peer a competent outsider would write (issue 16's
// reporter used one): each hypothesis pairs two sampled points with two landmarks the same
// distance apart (found by binary search in the sorted landmark pair distances), each landmark
// within the search radius of its point under the initial guess; the rigid correction of those
// two pairs is scored by its inlier count (points within a threshold of a landmark, looked up in a
// grid); the number of samples adapts to the best inlier ratio; the winner is refined by least
// squares on its inliers. Unlike the nearest-landmark RANSAC (map_fit_peers.h) it does not need
// the initial guess to pair points with the right landmarks.
#pragma once

#include <Eigen/Core>
#include <span>

#include "geometry/pose2.h"
#include "mapmatch/map_fit.h"

namespace fleetloc::peers {

struct PairRansacOptions {
  // The prior: a sampled point pairs only with landmarks this close to it under `initial` (the
  // search radius hint); 0: with any landmark.
  double search_radius_m = 0.0;
  double inlier_threshold_m = 0.03;  // a point this close to a landmark is an inlier (3σ at 1 cm)
  // Two distances agree within this; 0: twice the inlier threshold (both ends may be that far off).
  double distance_tolerance_m = 0.0;
  double min_pair_distance_m = 0.2;  // closer sampled points do not fix the rotation; skipped
  double confidence = 0.99;          // of having drawn two inliers, for the adaptive sample count
  int max_hypotheses = 5000;         // corrections scored, at most
  int max_samples = 50000;           // point pairs drawn, at most (most find no landmark pair)
  int refine_rounds = 3;             // least squares on the inliers, re-paired each round
  int min_inliers = 4;               // fewer after refinement: no model
  unsigned seed = 1;                 // the sampler's; the fit is deterministic
};

// The correction T moving `points` onto `landmarks`, searched around `initial`. `iterations` is
// the number of hypotheses scored, `inliers` and `landmarks_matched` count the points within the
// inlier threshold of a landmark under T and the landmarks they land on. `converged` false (with
// the reason) when no hypothesis reaches min_inliers. Requires non-empty, finite inputs.
mapmatch::MapFitResult PairRansacMapFit(std::span<const Eigen::Vector2d> landmarks,
                                        std::span<const Eigen::Vector2d> points,
                                        const geometry::Pose2& initial,
                                        const PairRansacOptions& options = {});

}  // namespace fleetloc::peers
