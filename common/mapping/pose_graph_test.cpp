// Tests for the SE(2) pose graph: analytic Jacobians against finite differences, recovery of known
// poses through a loop closure from badly drifted odometry, and the anchoring checks.
#include "mapping/pose_graph.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace fleetloc::mapping {
namespace {

using geometry::Pose2;

Eigen::Matrix3d Information(double sigma_m, double sigma_rad) {
  return Eigen::Vector3d(1 / (sigma_m * sigma_m), 1 / (sigma_m * sigma_m),
                         1 / (sigma_rad * sigma_rad))
      .asDiagonal();
}

// Camera poses on a circle of radius 1 m, heading along the circle.
Pose2 CirclePose(int k, int count) {
  const double s = 2 * M_PI * k / count;
  return {std::cos(s), std::sin(s), geometry::WrapAngle(s + M_PI / 2)};
}

TEST(PoseGraph, EdgeJacobiansMatchFiniteDifferences) {
  const Pose2 a{0.3, -1.2, 2.9}, b{1.1, 0.4, -2.8}, z{0.5, 0.2, 0.7};
  const Eigen::Matrix3d ja = EdgeJacobianFrom(a, b), jb = EdgeJacobianTo(a);
  const double h = 1e-7;
  for (int k = 0; k < 3; ++k) {
    Eigen::Vector3d d = Eigen::Vector3d::Zero();
    d[k] = h;
    const Eigen::Vector3d numeric_a = (EdgeResidual(Pose2::FromVector(a.ToVector() + d), b, z) -
                                       EdgeResidual(Pose2::FromVector(a.ToVector() - d), b, z)) /
                                      (2 * h);
    const Eigen::Vector3d numeric_b = (EdgeResidual(a, Pose2::FromVector(b.ToVector() + d), z) -
                                       EdgeResidual(a, Pose2::FromVector(b.ToVector() - d), z)) /
                                      (2 * h);
    EXPECT_LT((ja.col(k) - numeric_a).norm(), 1e-7) << "d/d a[" << k << "]";
    EXPECT_LT((jb.col(k) - numeric_b).norm(), 1e-7) << "d/d b[" << k << "]";
  }
}

TEST(PoseGraph, LoopClosureRecoversKnownPosesFromDriftedOdometry) {
  const int count = 24, gap = 11;  // no registration between frames 11 and 12
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 1.0);
  PoseGraph graph;
  Pose2 dead_reckoned = CirclePose(0, count);
  graph.AddNode(dead_reckoned);
  for (int k = 1; k < count; ++k) {
    const Pose2 step = geometry::Between(CirclePose(k - 1, count), CirclePose(k, count));
    // Odometry: 3 % scale error, a heading bias and noise: tens of centimetres off after a lap.
    const Pose2 odometry{step.x * 1.03 + 0.01 * noise(rng), step.y * 1.03 + 0.01 * noise(rng),
                         step.theta + 0.02 + 0.01 * noise(rng)};
    dead_reckoned = dead_reckoned * odometry;
    graph.AddNode(dead_reckoned);
    graph.AddEdge({k - 1, k, odometry, Information(0.02, 0.02), EdgeKind::kOdometry});
    if (k - 1 != gap) {
      graph.AddEdge({k - 1, k, step, Information(1e-7, 1e-7), EdgeKind::kRegistration});
    }
  }
  // Frames 12..23 reach the anchor only through the loop closure 23 → 0 (and the weak odometry).
  graph.AddEdge({count - 1, 0,
                 geometry::Between(CirclePose(count - 1, count), CirclePose(0, count)),
                 Information(1e-7, 1e-7), EdgeKind::kLoopClosure});
  ASSERT_GT(std::hypot(dead_reckoned.x - CirclePose(count - 1, count).x,
                       dead_reckoned.y - CirclePose(count - 1, count).y),
            0.2);

  const Result<PoseGraphSolveSummary> summary = graph.Solve();
  ASSERT_TRUE(summary.ok()) << summary.status().message();
  EXPECT_TRUE(summary->converged);
  EXPECT_LT(summary->final_cost, summary->initial_cost);
  for (int k = 0; k < count; ++k) {
    const Pose2 truth = CirclePose(k, count), solved = graph.poses()[k];
    EXPECT_NEAR(solved.x, truth.x, 1e-6) << "frame " << k;
    EXPECT_NEAR(solved.y, truth.y, 1e-6) << "frame " << k;
    EXPECT_NEAR(geometry::WrapAngle(solved.theta - truth.theta), 0.0, 1e-6) << "frame " << k;
  }
}

TEST(PoseGraph, AnchorStaysAtItsInitialPose) {
  PoseGraph graph;
  const Pose2 anchor{2.0, -1.0, 0.4};
  graph.AddNode(anchor);
  graph.AddNode({0, 0, 0});
  graph.AddEdge({0, 1, {0.1, 0.2, 0.3}, Information(1e-3, 1e-3), EdgeKind::kRegistration});
  ASSERT_TRUE(graph.Solve().ok());
  EXPECT_DOUBLE_EQ(graph.poses()[0].x, anchor.x);
  const Pose2 expected = anchor * Pose2{0.1, 0.2, 0.3};
  EXPECT_NEAR(graph.poses()[1].x, expected.x, 1e-12);
  EXPECT_NEAR(graph.poses()[1].y, expected.y, 1e-12);
  EXPECT_NEAR(graph.poses()[1].theta, expected.theta, 1e-12);
}

TEST(PoseGraph, SpanningTreeFollowsTheMostInformativeEdges) {
  PoseGraph graph;
  for (int k = 0; k < 3; ++k) graph.AddNode({5.0, 5.0, 1.0});  // far from anything
  const Pose2 a{1.0, 0.0, M_PI / 2}, b{1.0, 0.0, 0.0};
  graph.AddEdge({0, 1, a, Information(1e-4, 1e-4), EdgeKind::kRegistration});
  graph.AddEdge({2, 1, b, Information(1e-4, 1e-4), EdgeKind::kRegistration});          // reversed
  graph.AddEdge({0, 2, {9.0, 9.0, 0.0}, Information(1.0, 1.0), EdgeKind::kOdometry});  // weak
  graph.ResetToSpanningTree();
  const Pose2 two = a * b.Inverse();            // 0 → 1 → 2 through the strong edges
  EXPECT_NEAR(graph.poses()[0].x, 5.0, 1e-12);  // the anchor stays
  EXPECT_NEAR(graph.poses()[2].x, (graph.poses()[0] * two).x, 1e-12);
  EXPECT_NEAR(graph.poses()[2].y, (graph.poses()[0] * two).y, 1e-12);
  EXPECT_NEAR(graph.poses()[2].theta, (graph.poses()[0] * two).theta, 1e-12);
}

TEST(PoseGraph, NodeWithoutActiveEdgesIsReportedNotSolved) {
  PoseGraph graph;
  graph.AddNode({});
  graph.AddNode({});
  graph.AddNode({});
  graph.AddEdge({0, 1, {0.1, 0, 0}, Information(1e-3, 1e-3), EdgeKind::kOdometry});
  const int edge = graph.AddEdge({1, 2, {0.1, 0, 0}, Information(1e-3, 1e-3), EdgeKind::kOdometry});
  graph.SetActive(edge, false);
  const Result<PoseGraphSolveSummary> summary = graph.Solve();
  ASSERT_FALSE(summary.ok());
  EXPECT_EQ(summary.status().code(), StatusCode::kInvalidInput);
  EXPECT_NE(summary.status().message().find("frame 2"), std::string::npos)
      << summary.status().message();
}

}  // namespace
}  // namespace fleetloc::mapping
