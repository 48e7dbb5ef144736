// An SE(2) pose graph over the frames of a mapping run: nodes are camera_ground poses in map,
// edges are measured relative poses (odometry increments, frame registrations, loop closures)
// with their information matrices. The first node is the anchor and never moves.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "base/status.h"
#include "geometry/pose2.h"

namespace fleetloc::mapping {

enum class EdgeKind { kOdometry, kRegistration, kLoopClosure };

// "odometry", "registration", "loop closure" (for messages).
const char* EdgeKindName(EdgeKind kind);

struct PoseGraphEdge {
  int from = 0;
  int to = 0;
  geometry::Pose2 measured;                                   // pose of `to` in the frame of `from`
  Eigen::Matrix3d information = Eigen::Matrix3d::Identity();  // inverse covariance of measured
  EdgeKind kind = EdgeKind::kOdometry;
  bool active = true;  // inactive edges are kept but ignored by Solve
};

struct PoseGraphSolveOptions {
  int max_iterations = 50;
  double initial_lambda = 1e-6;   // Levenberg–Marquardt damping, relative to the diagonal
  double step_tolerance = 1e-12;  // stop when every step component is below this (m, rad)
};

struct PoseGraphSolveSummary {
  int iterations = 0;
  double initial_cost = 0.0;  // ½ Σ eᵀ Ω e over active edges
  double final_cost = 0.0;
  bool converged = false;
};

// Residual of an edge for poses a (its `from`) and b (its `to`): the parameters of
// (a⁻¹ ⊕ b) minus the measured ones, angle wrapped: [Rₐᵀ(t_b − t_a) − t_z; θ_b − θ_a − θ_z].
Eigen::Vector3d EdgeResidual(const geometry::Pose2& a, const geometry::Pose2& b,
                             const geometry::Pose2& measured);
// Its Jacobians with respect to a and b.
Eigen::Matrix3d EdgeJacobianFrom(const geometry::Pose2& a, const geometry::Pose2& b);
Eigen::Matrix3d EdgeJacobianTo(const geometry::Pose2& a);

class PoseGraph {
 public:
  // Adds a node with its initial estimate; returns its index. Node 0 is the anchor.
  int AddNode(const geometry::Pose2& initial);
  // Adds an edge; requires valid, distinct node indices and a symmetric positive definite
  // information matrix (checked). Returns its index.
  int AddEdge(const PoseGraphEdge& edge);

  // Levenberg–Marquardt over all nodes but the anchor, on the active edges. InvalidInput when
  // some node is connected to the anchor by no active edge (the system is singular) — the
  // message names the first such node.
  Result<PoseGraphSolveSummary> Solve(const PoseGraphSolveOptions& options = {});

  // Re-initializes every node reachable from the anchor by composing measurements along the
  // spanning tree of the most informative active edges (largest det Ω first, Prim's order), so
  // all residual sits on the edges outside the tree. Gauss–Newton in absolute coordinates turns
  // long stiff chains poorly (a linearized rotation stretches every strong edge to second order),
  // so a solve after removing edges should start from here rather than from the previous optimum.
  void ResetToSpanningTree();

  // ½ eᵀ Ω e of one edge at the current poses: its χ²/2 when Ω is the true inverse covariance.
  double EdgeCost(int edge) const;

  void SetActive(int edge, bool active) { edges_.at(edge).active = active; }
  void SetPose(int node, const geometry::Pose2& pose) { poses_.at(node) = pose; }
  const std::vector<geometry::Pose2>& poses() const { return poses_; }
  const std::vector<PoseGraphEdge>& edges() const { return edges_; }
  int node_count() const { return static_cast<int>(poses_.size()); }

 private:
  double TotalCost(const std::vector<geometry::Pose2>& poses) const;
  // The first node (> 0) with no path of active edges to the anchor, or -1.
  int FirstUnanchoredNode() const;

  std::vector<geometry::Pose2> poses_;
  std::vector<PoseGraphEdge> edges_;
};

}  // namespace fleetloc::mapping
