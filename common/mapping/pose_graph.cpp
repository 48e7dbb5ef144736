// SE(2) pose graph and its Levenberg–Marquardt solver.
//
// Why a small solver here instead of Ceres or g2o: the mapping graph is a chain of a few hundred
// to a few thousand 3-DOF nodes with a handful of loop closures — its normal equations are a
// banded sparse matrix that Eigen's SimplicialLDLT (already a dependency) factors in
// milliseconds. Writing the residual, its two 3×3 Jacobians and a damped Gauss–Newton loop takes
// about a hundred lines; a solver library would add a large dependency (Ceres is not one of the
// project's) for no measurable gain at this size.
#include "mapping/pose_graph.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <cmath>
#include <numeric>
#include <queue>
#include <string>
#include <utility>

namespace fleetloc::mapping {

using geometry::Pose2;

const char* EdgeKindName(EdgeKind kind) {
  switch (kind) {
    case EdgeKind::kOdometry:
      return "odometry";
    case EdgeKind::kRegistration:
      return "registration";
    case EdgeKind::kLoopClosure:
      return "loop closure";
  }
  return "edge";
}

Eigen::Vector3d EdgeResidual(const Pose2& a, const Pose2& b, const Pose2& measured) {
  const Pose2 between = geometry::Between(a, b);
  return {between.x - measured.x, between.y - measured.y,
          geometry::WrapAngle(between.theta - measured.theta)};
}

Eigen::Matrix3d EdgeJacobianFrom(const Pose2& a, const Pose2& b) {
  const double c = std::cos(a.theta), s = std::sin(a.theta);
  const double dx = b.x - a.x, dy = b.y - a.y;
  Eigen::Matrix3d j;
  j << -c, -s, -s * dx + c * dy,  //
      s, -c, -c * dx - s * dy,    //
      0, 0, -1;
  return j;
}

Eigen::Matrix3d EdgeJacobianTo(const Pose2& a) {
  const double c = std::cos(a.theta), s = std::sin(a.theta);
  Eigen::Matrix3d j;
  j << c, s, 0,  //
      -s, c, 0,  //
      0, 0, 1;
  return j;
}

int PoseGraph::AddNode(const Pose2& initial) {
  poses_.push_back(initial);
  return node_count() - 1;
}

int PoseGraph::AddEdge(const PoseGraphEdge& edge) {
  FLEETLOC_CHECK(edge.from >= 0 && edge.from < node_count());
  FLEETLOC_CHECK(edge.to >= 0 && edge.to < node_count() && edge.to != edge.from);
  FLEETLOC_CHECK(edge.information.isApprox(edge.information.transpose()));
  FLEETLOC_CHECK(edge.information.llt().info() == Eigen::Success);
  edges_.push_back(edge);
  return static_cast<int>(edges_.size()) - 1;
}

double PoseGraph::EdgeCost(int index) const {
  const PoseGraphEdge& e = edges_.at(index);
  const Eigen::Vector3d r = EdgeResidual(poses_[e.from], poses_[e.to], e.measured);
  return 0.5 * r.dot(e.information * r);
}

double PoseGraph::TotalCost(const std::vector<Pose2>& poses) const {
  double cost = 0.0;
  for (const PoseGraphEdge& e : edges_) {
    if (!e.active) continue;
    const Eigen::Vector3d r = EdgeResidual(poses[e.from], poses[e.to], e.measured);
    cost += 0.5 * r.dot(e.information * r);
  }
  return cost;
}

int PoseGraph::FirstUnanchoredNode() const {
  std::vector<int> parent(poses_.size());
  std::iota(parent.begin(), parent.end(), 0);
  const auto root = [&parent](int i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  for (const PoseGraphEdge& e : edges_) {
    if (e.active) parent[root(e.from)] = root(e.to);
  }
  for (int i = 1; i < node_count(); ++i) {
    if (root(i) != root(0)) return i;
  }
  return -1;
}

void PoseGraph::ResetToSpanningTree() {
  std::vector<std::vector<int>> incident(poses_.size());
  for (int e = 0; e < static_cast<int>(edges_.size()); ++e) {
    if (!edges_[e].active) continue;
    incident[edges_[e].from].push_back(e);
    incident[edges_[e].to].push_back(e);
  }
  // Prim's algorithm on det Ω: a max-heap of edges leaving the tree.
  std::vector<bool> in_tree(poses_.size(), false);
  std::priority_queue<std::pair<double, int>> frontier;
  const auto enter = [&](int node) {
    in_tree[node] = true;
    for (int e : incident[node]) frontier.push({edges_[e].information.determinant(), e});
  };
  enter(0);
  while (!frontier.empty()) {
    const PoseGraphEdge& e = edges_[frontier.top().second];
    frontier.pop();
    if (in_tree[e.from] == in_tree[e.to]) continue;
    if (in_tree[e.from]) {
      poses_[e.to] = poses_[e.from] * e.measured;
      enter(e.to);
    } else {
      poses_[e.from] = poses_[e.to] * e.measured.Inverse();
      enter(e.from);
    }
  }
}

namespace {

// Gauss–Newton normal equations H Δ = −g over the non-anchor nodes (variable block i − 1).
struct NormalEquations {
  Eigen::SparseMatrix<double> hessian;
  Eigen::VectorXd gradient;
};

NormalEquations Linearize(const std::vector<Pose2>& poses,
                          const std::vector<PoseGraphEdge>& edges) {
  const int n = static_cast<int>(poses.size()) - 1;
  std::vector<Eigen::Triplet<double>> triplets;
  NormalEquations eq{Eigen::SparseMatrix<double>(3 * n, 3 * n), Eigen::VectorXd::Zero(3 * n)};
  const auto add_block = [&triplets](int row_node, int col_node, const Eigen::Matrix3d& block) {
    if (row_node == 0 || col_node == 0) return;  // the anchor is not a variable
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) {
        triplets.emplace_back(3 * (row_node - 1) + r, 3 * (col_node - 1) + c, block(r, c));
      }
    }
  };
  for (const PoseGraphEdge& e : edges) {
    if (!e.active) continue;
    const Pose2& a = poses[e.from];
    const Pose2& b = poses[e.to];
    const Eigen::Vector3d r = EdgeResidual(a, b, e.measured);
    const Eigen::Matrix3d ja = EdgeJacobianFrom(a, b), jb = EdgeJacobianTo(a);
    add_block(e.from, e.from, ja.transpose() * e.information * ja);
    add_block(e.from, e.to, ja.transpose() * e.information * jb);
    add_block(e.to, e.from, jb.transpose() * e.information * ja);
    add_block(e.to, e.to, jb.transpose() * e.information * jb);
    if (e.from != 0) eq.gradient.segment<3>(3 * (e.from - 1)) += ja.transpose() * e.information * r;
    if (e.to != 0) eq.gradient.segment<3>(3 * (e.to - 1)) += jb.transpose() * e.information * r;
  }
  eq.hessian.setFromTriplets(triplets.begin(), triplets.end());
  return eq;
}

std::vector<Pose2> Apply(std::vector<Pose2> poses, const Eigen::VectorXd& step) {
  for (size_t i = 1; i < poses.size(); ++i) {
    const Eigen::Vector3d d = step.segment<3>(3 * (i - 1));
    poses[i] = {poses[i].x + d.x(), poses[i].y + d.y(),
                geometry::WrapAngle(poses[i].theta + d.z())};
  }
  return poses;
}

// H + λ·diag(H): Marquardt's damping, scale-invariant per variable.
Eigen::SparseMatrix<double> Damped(const Eigen::SparseMatrix<double>& hessian, double lambda) {
  Eigen::SparseMatrix<double> damped = hessian;
  for (int i = 0; i < damped.rows(); ++i) damped.coeffRef(i, i) *= 1.0 + lambda;
  return damped;
}

constexpr double kMaxLambda = 1e12;

}  // namespace

Result<PoseGraphSolveSummary> PoseGraph::Solve(const PoseGraphSolveOptions& options) {
  if (const int node = FirstUnanchoredNode(); node >= 0) {
    return InvalidInput("pose graph: frame " + std::to_string(node) +
                        " is linked to the first frame by no measurement");
  }
  PoseGraphSolveSummary summary;
  double cost = summary.initial_cost = summary.final_cost = TotalCost(poses_);
  if (node_count() < 2) {
    summary.converged = true;
    return summary;
  }
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt;
  double lambda = options.initial_lambda;
  bool pattern_analyzed = false;
  while (summary.iterations < options.max_iterations && !summary.converged) {
    ++summary.iterations;
    const NormalEquations eq = Linearize(poses_, edges_);
    if (!pattern_analyzed) ldlt.analyzePattern(eq.hessian);
    pattern_analyzed = true;
    bool accepted = false;
    while (!accepted && lambda < kMaxLambda) {
      ldlt.factorize(Damped(eq.hessian, lambda));
      if (ldlt.info() != Eigen::Success) {
        lambda *= 10.0;
        continue;
      }
      const Eigen::VectorXd step = ldlt.solve(-eq.gradient);
      std::vector<Pose2> candidate = Apply(poses_, step);
      const double candidate_cost = TotalCost(candidate);
      summary.converged = step.lpNorm<Eigen::Infinity>() < options.step_tolerance;
      if (candidate_cost <= cost) {
        poses_ = std::move(candidate);
        cost = candidate_cost;
        lambda = std::max(lambda / 10.0, 1e-15);
        accepted = true;
      } else if (summary.converged) {
        break;  // at the floor of rounding: the step no longer lowers the cost
      } else {
        lambda *= 10.0;
      }
    }
    if (!accepted && !summary.converged) break;  // damping exhausted: keep the best poses
  }
  summary.final_cost = cost;
  return summary;
}

}  // namespace fleetloc::mapping
