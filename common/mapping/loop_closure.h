// Loop closures of a mapping run: frames far apart along the route whose footprints overlap at the
// current estimate (where the route crosses or revisits itself), the uncertainty of their relative
// pose accumulated along the chain of successive frames (which sets the search window), and the
// robust gates that keep wrong registrations out of the pose graph.
#pragma once

#include <vector>

#include "base/status.h"
#include "geometry/camera_model.h"
#include "geometry/pose2.h"
#include "mapping/pose_graph.h"

namespace fleetloc::mapping {

struct LoopClosureOptions {
  double min_overlap_fraction = 0.5;  // share of a frame's footprint the other one covers
  double min_route_gap = 1.0;  // the route between the frames is ≥ this × the footprint diagonal
  int max_per_frame = 2;       // closures tried per later frame, best overlap first
  int max_total = 400;
  double sigma_inflation = 2.0;  // the chain's 1-sigma × this: search window and gate
  double gate_chi2 = 16.27;      // 3 degrees of freedom, 99.9 %
  // Closures outside the gate of the chain's prediction are kept only when at least this many of
  // them remain consistent after solving (the chain, e.g. across an odometry bridge, was off).
  int min_corroborating = 3;
};

// Flat range checks; InvalidInput naming the field.
Status Validate(const LoopClosureOptions& options);

struct LoopCandidate {
  int from = 0;  // earlier frame
  int to = 0;    // later frame
  double overlap = 0.0;
};

// Pairs of frames whose footprints (camera_ground poses `poses`) overlap by at least
// min_overlap_fraction and that lie at least min_route_gap footprint diagonals apart along the
// route; for each later frame its best max_per_frame partners; at most max_total overall, ordered
// by later frame then earlier frame.
std::vector<LoopCandidate> FindLoopCandidates(const std::vector<geometry::Pose2>& poses,
                                              const geometry::CameraModel& camera,
                                              const LoopClosureOptions& options);

// The relative pose of frame `to` in frame `from` (from < to) with its covariance, composed along
// `steps` (steps[k] takes frame k to frame k + 1; size ≥ to).
geometry::PoseWithCovariance ComposeChain(const std::vector<geometry::PoseWithCovariance>& steps,
                                          int from, int to);

// Squared Mahalanobis distance between a measured and a predicted relative pose whose errors are
// independent: dᵀ (Σ_measured + Σ_predicted)⁻¹ d, angle difference wrapped.
double GateDistance(const geometry::PoseWithCovariance& measured,
                    const geometry::PoseWithCovariance& predicted);

// Robust pruning after a solve: while the loop-closure edge with the largest χ² (2 × its cost)
// exceeds gate_chi2, deactivate it and solve again. Returns the number of edges deactivated;
// a failed solve is returned as is.
Result<int> PruneInconsistentLoopClosures(PoseGraph* graph, double gate_chi2,
                                          const PoseGraphSolveOptions& solve);

// Closures far from the chain's prediction (`surprising` edge indices) are trusted only together:
// when fewer than min_corroborating of them are still active, all are deactivated — a lone one
// may be a wrong match that pruning cannot see, because a weak odometry bridge gives way to it.
// Returns the number deactivated.
int DropUncorroborated(PoseGraph* graph, const std::vector<int>& surprising, int min_corroborating);

}  // namespace fleetloc::mapping
