// Loop-closure candidates, chain uncertainty and gates.
#include "mapping/loop_closure.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

#include "geometry/footprint.h"

namespace fleetloc::mapping {

using geometry::Pose2;

Status Validate(const LoopClosureOptions& o) {
  if (!(o.min_overlap_fraction > 0 && o.min_overlap_fraction <= 1)) {
    return InvalidInput("loops.min_overlap_fraction must be in (0, 1]");
  }
  if (!(o.min_route_gap >= 1)) return InvalidInput("loops.min_route_gap must be ≥ 1");
  if (o.max_per_frame < 0 || o.max_total < 0) {
    return InvalidInput("loops.max_per_frame and max_total must be ≥ 0");
  }
  if (!(o.sigma_inflation >= 1)) return InvalidInput("loops.sigma_inflation must be ≥ 1");
  if (!(o.gate_chi2 > 0)) return InvalidInput("loops.gate_chi2 must be > 0");
  if (o.min_corroborating < 1) return InvalidInput("loops.min_corroborating must be ≥ 1");
  return Status::Ok();
}

std::vector<LoopCandidate> FindLoopCandidates(const std::vector<Pose2>& poses,
                                              const geometry::CameraModel& camera,
                                              const LoopClosureOptions& options) {
  const geometry::ConvexPolygon ground = geometry::FootprintInGround(camera);
  const double diagonal = std::hypot(camera.width_px, camera.height_px) * camera.resolution_m;
  std::vector<geometry::ConvexPolygon> placed;
  std::vector<double> route_m{0.0};  // distance driven up to each frame
  for (size_t k = 0; k < poses.size(); ++k) {
    placed.push_back(geometry::PlaceFootprint(ground, poses[k]));
    if (k > 0) {
      route_m.push_back(route_m.back() +
                        std::hypot(poses[k].x - poses[k - 1].x, poses[k].y - poses[k - 1].y));
    }
  }
  std::vector<LoopCandidate> all;
  for (size_t j = 0; j < poses.size(); ++j) {
    std::vector<LoopCandidate> partners;
    for (size_t i = 0; i < j; ++i) {
      if (route_m[j] - route_m[i] < options.min_route_gap * diagonal) break;
      if (std::hypot(poses[j].x - poses[i].x, poses[j].y - poses[i].y) > diagonal) continue;
      const double overlap = geometry::OverlapFraction(placed[j], placed[i]);
      if (overlap >= options.min_overlap_fraction) {
        partners.push_back({static_cast<int>(i), static_cast<int>(j), overlap});
      }
    }
    std::sort(partners.begin(), partners.end(),
              [](const LoopCandidate& a, const LoopCandidate& b) { return a.overlap > b.overlap; });
    if (static_cast<int>(partners.size()) > options.max_per_frame) {
      partners.resize(options.max_per_frame);
    }
    all.insert(all.end(), partners.begin(), partners.end());
  }
  if (static_cast<int>(all.size()) > options.max_total) {
    std::stable_sort(all.begin(), all.end(), [](const LoopCandidate& a, const LoopCandidate& b) {
      return a.overlap > b.overlap;
    });
    all.resize(options.max_total);
  }
  std::sort(all.begin(), all.end(), [](const LoopCandidate& a, const LoopCandidate& b) {
    return a.to != b.to ? a.to < b.to : a.from < b.from;
  });
  return all;
}

geometry::PoseWithCovariance ComposeChain(const std::vector<geometry::PoseWithCovariance>& steps,
                                          int from, int to) {
  FLEETLOC_CHECK(from >= 0 && from <= to && to <= static_cast<int>(steps.size()));
  geometry::PoseWithCovariance relative{Pose2{}, Eigen::Matrix3d::Zero()};
  for (int k = from; k < to; ++k) relative = geometry::Compose(relative, steps[k]);
  return relative;
}

double GateDistance(const geometry::PoseWithCovariance& measured,
                    const geometry::PoseWithCovariance& predicted) {
  const Eigen::Vector3d d(measured.pose.x - predicted.pose.x, measured.pose.y - predicted.pose.y,
                          geometry::WrapAngle(measured.pose.theta - predicted.pose.theta));
  return d.dot((measured.covariance + predicted.covariance).ldlt().solve(d));
}

Result<int> PruneInconsistentLoopClosures(PoseGraph* graph, double gate_chi2,
                                          const PoseGraphSolveOptions& solve) {
  int removed = 0;
  while (true) {
    int worst = -1;
    double worst_chi2 = gate_chi2;
    for (int e = 0; e < static_cast<int>(graph->edges().size()); ++e) {
      const PoseGraphEdge& edge = graph->edges()[e];
      if (!edge.active || edge.kind != EdgeKind::kLoopClosure) continue;
      const double chi2 = 2.0 * graph->EdgeCost(e);
      if (chi2 > worst_chi2) {
        worst_chi2 = chi2;
        worst = e;
      }
    }
    if (worst < 0) return removed;
    graph->SetActive(worst, false);
    ++removed;
    const Result<PoseGraphSolveSummary> solved = graph->Solve(solve);
    if (!solved.ok()) return solved.status();
  }
}

int DropUncorroborated(PoseGraph* graph, const std::vector<int>& surprising,
                       int min_corroborating) {
  int active = 0;
  for (int edge : surprising) active += graph->edges()[edge].active ? 1 : 0;
  if (active == 0 || active >= min_corroborating) return 0;
  for (int edge : surprising) graph->SetActive(edge, false);
  return active;
}

}  // namespace fleetloc::mapping
