// Pose voting for global relocalization: every descriptor match between a camera frame and the
// place index votes for a camera pose (the map feature's position and heading minus the frame
// feature's offset and orientation); consistent votes are clustered by heading and by mean shift
// over position, and each cluster's matches are fitted with a rigid transform — a short list of
// candidate poses, best supported first.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "base/status.h"
#include "geometry/pose2.h"

namespace fleetloc::relocalization {

// One match: a frame feature at `ground_m` (camera_ground) with orientation `ground_heading_rad`
// and an index feature at `map_m` with `map_heading_rad`. `query` names the frame feature (one
// frame feature may vote several times, through several index features).
struct FeatureMatch {
  int query = 0;
  Eigen::Vector2d ground_m = Eigen::Vector2d::Zero();
  double ground_heading_rad = 0.0;
  Eigen::Vector2d map_m = Eigen::Vector2d::Zero();
  double map_heading_rad = 0.0;
};

struct VoteClusterOptions {
  double radius_m = 0.02;               // mean-shift radius over voted camera positions
  double heading_tolerance_rad = 0.26;  // votes within this of a cluster's heading join it
  int max_candidates = 6;
  int min_support = 6;               // votes a cluster needs to become a candidate
  double inlier_distance_m = 0.003;  // rigid fit: a match within this of its map point
};

// Flat range checks; InvalidInput naming the field.
Status Validate(const VoteClusterOptions& options);

struct PoseCandidate {
  geometry::Pose2 camera_in_map;  // camera_ground in map from the rigid fit of the inliers
  int support = 0;                // votes in the mean-shift cluster
  int inliers = 0;                // distinct frame features within inlier_distance after the fit
  double rms_m = 0.0;             // fit residual of the inliers
};

// The camera pose a match votes for.
geometry::Pose2 VotedPose(const FeatureMatch& match);

// The rigid transform (camera_ground → map) best fitting the matches in the least-squares sense
// (2-D Procrustes). Requires at least two matches.
geometry::Pose2 FitRigid(const std::vector<FeatureMatch>& matches);

// Candidates (at most max_candidates, distinct by more than radius or heading tolerance), most
// inliers first. Options must have passed Validate(). Empty when no cluster has min_support votes.
std::vector<PoseCandidate> ClusterVotes(const std::vector<FeatureMatch>& matches,
                                        const VoteClusterOptions& options);

}  // namespace fleetloc::relocalization
