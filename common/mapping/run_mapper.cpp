// Mapping-run poses: successive registration, chain solve, loop closures, final solve.
#include "mapping/run_mapper.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <list>
#include <utility>

#include "geometry/footprint.h"
#include "tracking/motion_model.h"

namespace fleetloc::mapping {
namespace {

using geometry::Pose2;
using geometry::PoseWithCovariance;

constexpr size_t kCachedFrames = 16;
constexpr int kProgressLines = 10;  // per stage

// A few decoded frames kept for reuse: successive pairs and loop closures share frames.
class FrameCache {
 public:
  explicit FrameCache(const FrameLoader& loader) : loader_(loader) {}

  Result<cv::Mat> Get(int index) {
    for (auto it = entries_.begin(); it != entries_.end(); ++it) {
      if (it->first != index) continue;
      entries_.splice(entries_.begin(), entries_, it);
      return it->second;
    }
    Result<cv::Mat> frame = loader_(index);
    if (!frame.ok()) return frame;
    entries_.emplace_front(index, *frame);
    if (entries_.size() > kCachedFrames) entries_.pop_back();
    return frame;
  }

 private:
  const FrameLoader& loader_;
  std::list<std::pair<int, cv::Mat>> entries_;  // most recently used first
};

Eigen::Matrix3d Information(const Eigen::Matrix3d& covariance) {
  const Eigen::Matrix3d information = covariance.inverse();
  return 0.5 * (information + information.transpose());
}

bool Finite(const Pose2& p) {
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.theta);
}

Status ValidateInput(const MapperInput& in) {
  const size_t n = in.frame_times_s.size();
  if (n < 2) return InvalidInput("a mapping run needs at least 2 frames");
  if (in.odometry.size() != n) return InvalidInput("one odometry pose per frame is needed");
  if (!Finite(in.initial_base_in_map)) return InvalidInput("initial pose is not finite");
  for (size_t k = 0; k < n; ++k) {
    if (!Finite(in.odometry[k]) || !std::isfinite(in.frame_times_s[k])) {
      return InvalidInput("odometry at frame " + std::to_string(k) + " is not finite");
    }
    if (k > 0 && !(in.frame_times_s[k] > in.frame_times_s[k - 1])) {
      return InvalidInput("frame " + std::to_string(k) + " is not after the previous one");
    }
  }
  return Status::Ok();
}

// True when `done` of `total` is at one of kProgressLines evenly spaced marks or the end.
bool ProgressMark(int done, int total) {
  const int every = std::max(1, total / kProgressLines);
  return done % every == 0 || done == total;
}

class Mapper {
 public:
  Mapper(const MapperInput& input, const FrameLoader& loader, const MapperOptions& options,
         const MapperLog& log)
      : in_(input),
        options_(options),
        log_(log),
        frames_(loader),
        registrar_(options.registration, input.camera) {}

  Result<MappedRun> Run() {
    FLEETLOC_RETURN_IF_ERROR(RegisterSuccessive());
    FLEETLOC_RETURN_IF_ERROR(Solve("chain"));
    FLEETLOC_RETURN_IF_ERROR(CloseLoops());
    if (result_.loop_registered > 0) FLEETLOC_RETURN_IF_ERROR(SolveWithLoops());
    result_.camera_in_map = graph_.poses();
    return std::move(result_);
  }

 private:
  int frame_count() const { return static_cast<int>(in_.frame_times_s.size()); }

  void Log(const std::string& line) const {
    if (log_) log_(line);
  }

  // The camera's odometry increment from frame i to frame k with its covariance.
  PoseWithCovariance OdometryStep(int i, int k) const {
    return tracking::CameraIncrement(in_.odometry[i], in_.odometry[k],
                                     in_.frame_times_s[k] - in_.frame_times_s[i], in_.camera.mount,
                                     options_.odometry);
  }

  // Node k starts at node k-1 ⊕ its odometry step (node 0 at the run's initial pose).
  void AddFrameNode(int k) {
    if (k == 0) {
      graph_.AddNode(in_.initial_base_in_map * in_.camera.mount);
      return;
    }
    steps_.push_back(OdometryStep(k - 1, k));
    graph_.AddNode(graph_.poses()[k - 1] * steps_.back().pose);
  }

  // The odometry edge k-1 → k bridges a pair that did not register. Where the pair registered it
  // is left out: wheel odometry errors are systematic (scale, heading drift), not the independent
  // noise a graph edge assumes, and registration measures the same increment about a hundred
  // times better — with the edge, the drift would bend the registered chain.
  void AddOdometryBridge(int k) {
    const PoseWithCovariance& step = steps_[k - 1];
    graph_.AddEdge({k - 1, k, step.pose, Information(step.covariance), EdgeKind::kOdometry});
    ++result_.odometry_bridges;
  }

  // True when frames i and k, placed at the current node poses, share at least `fraction`.
  bool Overlaps(int i, int k, double fraction) const {
    const geometry::ConvexPolygon ground = geometry::FootprintInGround(in_.camera);
    return geometry::OverlapFraction(geometry::PlaceFootprint(ground, graph_.poses()[k]),
                                     geometry::PlaceFootprint(ground, graph_.poses()[i])) >=
           fraction;
  }

  // Registers frame k against frame i (< k) around `predicted`: NotFound when they do not
  // register, the loader's error when a frame cannot be read.
  Result<FrameRegistration> RegisterPair(int i, int k, const PoseWithCovariance& predicted) {
    Result<cv::Mat> reference = frames_.Get(i);
    if (!reference.ok()) return reference.status();
    Result<cv::Mat> target = frames_.Get(k);
    if (!target.ok()) return target.status();
    return registrar_.Register(*reference, *target, predicted);
  }

  void AddRegistrationEdge(int i, int k, const FrameRegistration& r, EdgeKind kind) {
    graph_.AddEdge({i, k, r.relative.pose, Information(r.relative.covariance), kind});
  }

  Status RegisterSuccessive() {
    AddFrameNode(0);
    const int pairs = frame_count() - 1;
    for (int k = 1; k <= pairs; ++k) {
      AddFrameNode(k);
      bool placed = false;  // node k follows its first successful registration
      for (int d = 1; d <= options_.sequential_neighbours && k - d >= 0; ++d) {
        Result<bool> registered = RegisterSuccessivePair(k - d, k, !placed);
        if (!registered.ok()) return registered.status();
        placed = placed || *registered;
        if (d == 1 && !*registered) AddOdometryBridge(k);
      }
      if (ProgressMark(k, pairs)) {
        Log("registered " + std::to_string(k) + "/" + std::to_string(pairs) + " frames (" +
            std::to_string(result_.pairs_registered) + " of " +
            std::to_string(result_.pairs_tried) + " pairs)");
      }
    }
    if (result_.successive_registered < options_.min_registered_fraction * pairs) {
      return InvalidInput("only " + std::to_string(result_.successive_registered) + " of " +
                          std::to_string(pairs) + " successive frame pairs registered (" +
                          std::to_string(successive_overlapping_) +
                          " overlap by the odometry): a mapping run needs overlapping frames "
                          "with texture");
    }
    return Status::Ok();
  }

  // Registers frame k against frame i when their predicted footprints overlap; true when it
  // registered. With `place`, node k moves to node i ⊕ the registration.
  Result<bool> RegisterSuccessivePair(int i, int k, bool place) {
    if (!Overlaps(i, k, options_.min_sequential_overlap)) return false;
    ++result_.pairs_tried;
    if (i == k - 1) ++successive_overlapping_;
    const PoseWithCovariance predicted{geometry::Between(graph_.poses()[i], graph_.poses()[k]),
                                       OdometryStep(i, k).covariance};
    Result<FrameRegistration> r = RegisterPair(i, k, predicted);
    if (!r.ok()) {
      if (r.status().code() != StatusCode::kNotFound) return r.status();  // unreadable frame
      return false;
    }
    ++result_.pairs_registered;
    AddRegistrationEdge(i, k, *r, EdgeKind::kRegistration);
    if (place) graph_.SetPose(k, graph_.poses()[i] * r->relative.pose);
    if (i == k - 1) {
      ++result_.successive_registered;
      steps_[i] = r->relative;
    }
    return true;
  }

  Status CloseLoops() {
    const std::vector<LoopCandidate> candidates =
        FindLoopCandidates(graph_.poses(), in_.camera, options_.loops);
    result_.loop_candidates = static_cast<int>(candidates.size());
    const double inflation_sq = std::pow(options_.loops.sigma_inflation, 2);
    for (size_t c = 0; c < candidates.size(); ++c) {
      const LoopCandidate& loop = candidates[c];
      const PoseWithCovariance predicted{
          geometry::Between(graph_.poses()[loop.from], graph_.poses()[loop.to]),
          inflation_sq * ComposeChain(steps_, loop.from, loop.to).covariance};
      Result<FrameRegistration> r = RegisterPair(loop.from, loop.to, predicted);
      if (!r.ok() && r.status().code() != StatusCode::kNotFound) return r.status();
      if (r.ok()) {
        ++result_.loop_registered;
        const int edge =
            graph_.AddEdge({loop.from, loop.to, r->relative.pose,
                            Information(r->relative.covariance), EdgeKind::kLoopClosure});
        if (GateDistance(r->relative, predicted) > options_.loops.gate_chi2) {
          outside_gate_edges_.push_back(edge);
        }
      }
      const int done = static_cast<int>(c) + 1;
      if (ProgressMark(done, result_.loop_candidates)) {
        Log("loop closures: tried " + std::to_string(done) + "/" +
            std::to_string(result_.loop_candidates) + ", registered " +
            std::to_string(result_.loop_registered) + " (" +
            std::to_string(outside_gate_edges_.size()) + " far from the chain's prediction)");
      }
    }
    result_.loop_outside_gate = static_cast<int>(outside_gate_edges_.size());
    if (candidates.empty()) Log("loop closures: the route never revisits itself");
    return Status::Ok();
  }

  // Solves with every registered loop closure, prunes those inconsistent with the rest, and
  // drops the closures far from the chain's prediction unless enough of them survive together
  // (several agreeing ones mean the chain was off; see DropUncorroborated).
  Status SolveWithLoops() {
    FLEETLOC_RETURN_IF_ERROR(Solve("with loop closures"));
    Result<int> pruned =
        PruneInconsistentLoopClosures(&graph_, options_.loops.gate_chi2, options_.solve);
    if (!pruned.ok()) return pruned.status();
    result_.loop_pruned = *pruned + DropUncorroborated(&graph_, outside_gate_edges_,
                                                       options_.loops.min_corroborating);
    if (result_.loop_pruned == 0) return Status::Ok();
    Log(std::to_string(result_.loop_pruned) +
        " loop closures inconsistent with the rest or uncorroborated: removed");
    graph_.ResetToSpanningTree();  // the optimum with them is a poor start without them
    return Solve("after pruning");
  }

  Status Solve(const std::string& stage) {
    Result<PoseGraphSolveSummary> s = graph_.Solve(options_.solve);
    if (!s.ok()) return s.status();
    result_.solves.push_back(*s);
    Log("pose graph (" + stage + "): " + std::to_string(graph_.node_count()) + " frames, " +
        std::to_string(graph_.edges().size()) + " edges, " + std::to_string(s->iterations) +
        " iterations, cost " + std::to_string(s->initial_cost) + " -> " +
        std::to_string(s->final_cost) + (s->converged ? "" : " (not converged)"));
    return Status::Ok();
  }

  const MapperInput& in_;
  const MapperOptions& options_;
  const MapperLog& log_;
  FrameCache frames_;
  FrameRegistrar registrar_;
  PoseGraph graph_;
  std::vector<PoseWithCovariance> steps_;  // best step k → k+1: registration, else odometry
  int successive_overlapping_ = 0;         // pairs (k-1, k) tried: they overlap by odometry
  std::vector<int> outside_gate_edges_;    // loop closures far from the chain's prediction
  MappedRun result_;
};

}  // namespace

Status Validate(const MapperOptions& o) {
  FLEETLOC_RETURN_IF_ERROR(Validate(o.registration));
  FLEETLOC_RETURN_IF_ERROR(Validate(o.loops));
  if (o.sequential_neighbours < 1) return InvalidInput("sequential_neighbours must be ≥ 1");
  if (!(o.min_sequential_overlap > 0 && o.min_sequential_overlap <= 1)) {
    return InvalidInput("min_sequential_overlap must be in (0, 1]");
  }
  if (!(o.min_registered_fraction >= 0 && o.min_registered_fraction <= 1)) {
    return InvalidInput("min_registered_fraction must be in [0, 1]");
  }
  if (o.solve.max_iterations < 1) return InvalidInput("solve.max_iterations must be ≥ 1");
  return Status::Ok();
}

Result<MappedRun> MapRun(const MapperInput& input, const FrameLoader& load_frame,
                         const MapperOptions& options, const MapperLog& log) {
  FLEETLOC_RETURN_IF_ERROR(Validate(options));
  FLEETLOC_RETURN_IF_ERROR(ValidateInput(input));
  return Mapper(input, load_frame, options, log).Run();
}

}  // namespace fleetloc::mapping
