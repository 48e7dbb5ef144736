// Tests for loop closures: candidates where a route crosses itself (and none between neighbours),
// chain uncertainty, the gate distance, and pruning of a wrong closure after a solve.
#include "mapping/loop_closure.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace fleetloc::mapping {
namespace {

using geometry::Pose2;

geometry::CameraModel Camera() {  // 100 × 80 px at 1 cm: a 1 m × 0.8 m footprint
  geometry::CameraModel camera;
  camera.width_px = 100;
  camera.height_px = 80;
  camera.cx_px = 50;
  camera.cy_px = 40;
  camera.resolution_m = 0.01;
  return camera;
}

// Ten frames east along y = 0 from x = -2.25, then ten frames north along x = 0 from y = -4.
std::vector<Pose2> CrossingRoute() {
  std::vector<Pose2> poses;
  for (int k = 0; k < 10; ++k) poses.push_back({-2.25 + 0.5 * k, 0.0, 0.0});
  for (int k = 0; k < 10; ++k) poses.push_back({0.0, -4.0 + 0.5 * k, M_PI / 2});
  return poses;
}

TEST(LoopClosure, CandidatesLieWhereTheRouteCrossesItself) {
  LoopClosureOptions options;
  options.min_overlap_fraction = 0.4;
  const std::vector<LoopCandidate> found = FindLoopCandidates(CrossingRoute(), Camera(), options);
  ASSERT_FALSE(found.empty());
  for (const LoopCandidate& c : found) {
    EXPECT_LT(c.from, 10) << "the earlier frame is on the eastward leg";
    EXPECT_GE(c.to, 10) << "the later frame is on the northward leg";
    EXPECT_GE(c.overlap, 0.4);
    EXPECT_LE(std::abs(CrossingRoute()[c.from].x), 0.5);
    EXPECT_LE(std::abs(CrossingRoute()[c.to].y), 0.5);
  }
  // The frame at the crossing itself (x = 0.25 / y = 0) pairs with its twin.
  EXPECT_NE(std::find_if(found.begin(), found.end(),
                         [](const LoopCandidate& c) { return c.from == 5 && c.to == 18; }),
            found.end());
}

TEST(LoopClosure, AtMostMaxPerFrameBestPartners) {
  LoopClosureOptions options;
  options.min_overlap_fraction = 0.1;
  options.max_per_frame = 1;
  const std::vector<LoopCandidate> found = FindLoopCandidates(CrossingRoute(), Camera(), options);
  for (size_t i = 1; i < found.size(); ++i) EXPECT_NE(found[i].to, found[i - 1].to);
}

TEST(LoopClosure, ChainComposesStepsAndTheirCovariance) {
  const geometry::PoseWithCovariance step{{1.0, 0.0, M_PI / 2},
                                          Eigen::Vector3d(1e-4, 1e-4, 1e-6).asDiagonal()};
  const std::vector<geometry::PoseWithCovariance> steps(4, step);
  const geometry::PoseWithCovariance two = ComposeChain(steps, 1, 3);
  EXPECT_NEAR(two.pose.x, 1.0, 1e-12);  // east 1 m, turn left, north 1 m
  EXPECT_NEAR(two.pose.y, 1.0, 1e-12);
  EXPECT_NEAR(two.pose.theta, M_PI, 1e-12);
  EXPECT_TRUE(two.covariance.isApprox(geometry::Compose(step, step).covariance));
  EXPECT_EQ(ComposeChain(steps, 2, 2).covariance.norm(), 0.0);
}

TEST(LoopClosure, GateDistanceIsTheMahalanobisDistanceOfTheDifference) {
  const geometry::PoseWithCovariance predicted{{0.0, 0.0, 3.1}, Eigen::Matrix3d::Identity() * 0.5};
  const geometry::PoseWithCovariance measured{{1.0, -2.0, -3.1}, Eigen::Matrix3d::Identity() * 0.5};
  const double dtheta = 2 * M_PI - 6.2;  // wrapped across ±π
  EXPECT_NEAR(GateDistance(measured, predicted), 1.0 + 4.0 + dtheta * dtheta, 1e-9);
}

TEST(LoopClosure, WrongClosureIsPrunedAndTheGoodOnesKept) {
  // A square of four frames, 1 m sides, with exact steps (σ 1 mm) and two loop closures back to
  // frame 0: one right, one 30 cm off.
  const Eigen::Matrix3d information = Eigen::Vector3d(1e6, 1e6, 1e6).asDiagonal();
  const Pose2 step{1.0, 0.0, M_PI / 2};
  PoseGraph graph;
  graph.AddNode({});
  for (int k = 1; k < 4; ++k) {
    graph.AddNode(graph.poses()[k - 1] * step);
    graph.AddEdge({k - 1, k, step, information, EdgeKind::kRegistration});
  }
  graph.AddEdge({0, 3, graph.poses()[3], information, EdgeKind::kLoopClosure});
  const int wrong =
      graph.AddEdge({1, 3, Pose2{1.3, 1.0, M_PI}, information, EdgeKind::kLoopClosure});
  ASSERT_TRUE(graph.Solve().ok());
  const Result<int> pruned = PruneInconsistentLoopClosures(&graph, 16.27, {});
  ASSERT_TRUE(pruned.ok());
  EXPECT_EQ(*pruned, 1);
  EXPECT_FALSE(graph.edges()[wrong].active);
  EXPECT_TRUE(graph.edges()[wrong - 1].active);
  EXPECT_NEAR(graph.poses()[3].x, 0.0, 1e-9);
  EXPECT_NEAR(graph.poses()[3].y, 1.0, 1e-9);
}

// Two registered chains (0 … 4 and 5 … 9, steps 1 m east) joined only by a weak odometry bridge
// 4 → 5, plus `loops` closures 9 → 0 .. 9 → loops-1 that all say chain B lies 0.3 m north.
PoseGraph BridgedChainsWithLoops(int loops, std::vector<int>* loop_edges) {
  const Eigen::Matrix3d strong = Eigen::Vector3d(1e8, 1e8, 1e8).asDiagonal();
  const Eigen::Matrix3d weak = Eigen::Vector3d(1e2, 1e2, 1e2).asDiagonal();
  const Pose2 step{1.0, 0.0, 0.0};
  PoseGraph graph;
  graph.AddNode({});
  for (int k = 1; k < 10; ++k) {
    graph.AddNode(graph.poses()[k - 1] * step);
    graph.AddEdge({k - 1, k, step, k == 5 ? weak : strong,
                   k == 5 ? EdgeKind::kOdometry : EdgeKind::kRegistration});
  }
  for (int i = 0; i < loops; ++i) {
    loop_edges->push_back(
        graph.AddEdge({9, i, Pose2{i - 9.0, -0.3, 0.0}, strong, EdgeKind::kLoopClosure}));
  }
  return graph;
}

TEST(LoopClosure, LoneSurprisingClosureAcrossABridgeIsDropped) {
  std::vector<int> loops;
  PoseGraph graph = BridgedChainsWithLoops(1, &loops);
  ASSERT_TRUE(graph.Solve().ok());
  // The bridge gives way: pruning alone cannot tell the closure is wrong.
  ASSERT_TRUE(PruneInconsistentLoopClosures(&graph, 16.27, {}).ok());
  EXPECT_TRUE(graph.edges()[loops[0]].active);
  EXPECT_EQ(DropUncorroborated(&graph, loops, 3), 1);
  EXPECT_FALSE(graph.edges()[loops[0]].active);
  graph.ResetToSpanningTree();
  const Result<PoseGraphSolveSummary> solved = graph.Solve();
  ASSERT_TRUE(solved.ok());
  EXPECT_TRUE(solved->converged);
  EXPECT_NEAR(graph.poses()[9].y, 0.0, 1e-9);
}

TEST(LoopClosure, SurprisingClosuresThatAgreeAreKept) {
  std::vector<int> loops;
  PoseGraph graph = BridgedChainsWithLoops(3, &loops);
  ASSERT_TRUE(graph.Solve().ok());
  EXPECT_EQ(DropUncorroborated(&graph, loops, 3), 0);
  EXPECT_NEAR(graph.poses()[9].y, 0.3, 1e-6);
}

}  // namespace
}  // namespace fleetloc::mapping
