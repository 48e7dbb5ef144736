// Pose voting: the vote of a single exact match, the rigid fit, and clustering with most matches
// wrong.
#include "relocalization/pose_votes.h"

#include <gtest/gtest.h>

#include <random>

namespace fleetloc::relocalization {
namespace {

// A match of the frame feature at `ground` seen by the camera at `camera` (exact, or moved to a
// random place of a 10 m floor when `outlier`).
FeatureMatch MatchOf(const geometry::Pose2& camera, int query, const Eigen::Vector2d& ground,
                     double ground_heading, std::mt19937_64& rng, bool outlier) {
  std::uniform_real_distribution<double> u(0.0, 10.0), angle(-M_PI, M_PI);
  FeatureMatch m{query, ground, ground_heading, camera * ground,
                 geometry::WrapAngle(camera.theta + ground_heading)};
  if (outlier) m.map_m = {u(rng), u(rng)}, m.map_heading_rad = angle(rng);
  return m;
}

TEST(PoseVotes, OneExactMatchVotesForTheTruePose) {
  std::mt19937_64 rng(1);
  const geometry::Pose2 camera{3.2, 1.7, 2.9};
  const geometry::Pose2 vote = VotedPose(MatchOf(camera, 0, {0.1, -0.08}, -2.0, rng, false));
  EXPECT_NEAR(vote.x, camera.x, 1e-12);
  EXPECT_NEAR(vote.y, camera.y, 1e-12);
  EXPECT_NEAR(geometry::WrapAngle(vote.theta - camera.theta), 0.0, 1e-12);
}

TEST(PoseVotes, ClusteringFindsThePoseWithEightyPercentWrongMatches) {
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<double> offset(-0.15, 0.15), angle(-M_PI, M_PI);
  std::normal_distribution<double> noise(0.0, 0.0005), heading_noise(0.0, 0.05);
  const geometry::Pose2 camera{4.0, 6.5, -1.1};
  std::vector<FeatureMatch> matches;
  for (int i = 0; i < 500; ++i) {
    FeatureMatch m = MatchOf(camera, i, {offset(rng), offset(rng)}, angle(rng), rng, i % 5 != 0);
    if (i % 5 == 0) {  // true match: position noise 0.5 mm, orientation noise 3°
      m.map_m += Eigen::Vector2d(noise(rng), noise(rng));
      m.map_heading_rad += heading_noise(rng);
    }
    matches.push_back(m);
  }
  const std::vector<PoseCandidate> found = ClusterVotes(matches, VoteClusterOptions{});
  ASSERT_FALSE(found.empty());
  const geometry::Pose2& best = found.front().camera_in_map;
  EXPECT_NEAR(best.x, camera.x, 0.0005);
  EXPECT_NEAR(best.y, camera.y, 0.0005);
  EXPECT_NEAR(geometry::WrapAngle(best.theta - camera.theta), 0.0, 0.005);
  EXPECT_GE(found.front().inliers, 90);  // of 100 true matches
}

TEST(PoseVotes, RandomMatchesGiveNoCandidate) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> offset(-0.15, 0.15);
  std::vector<FeatureMatch> matches;
  matches.reserve(300);
  for (int i = 0; i < 300; ++i)
    matches.push_back(MatchOf({}, i, {offset(rng), offset(rng)}, 0.0, rng, true));
  EXPECT_TRUE(ClusterVotes(matches, VoteClusterOptions{}).empty());
}

TEST(PoseVotes, BadOptionsAreRejected) {
  VoteClusterOptions options;
  options.inlier_distance_m = 1.0;  // above the radius
  EXPECT_FALSE(Validate(options).ok());
  options = {};
  options.heading_tolerance_rad = 0.0;
  EXPECT_FALSE(Validate(options).ok());
}

}  // namespace
}  // namespace fleetloc::relocalization
