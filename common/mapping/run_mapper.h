// The camera poses of a mapping run (docs/architecture.md, "register overlapping frames ..., make
// the result locally smooth"): successive frames registered with predictions from the odometry
// increments, an SE(2) pose graph of registration edges (and odometry edges bridging the pairs
// that did not register) solved; loop closures found where the route revisits itself, registered,
// added and solved again with robust pruning. Anchored at the first frame's pose, so the result
// lives in the map frame of the run's initial pose. Pure: frames come through a loader, messages
// go to a callback.
#pragma once

#include <functional>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "base/status.h"
#include "geometry/camera_model.h"
#include "mapping/frame_registration.h"
#include "mapping/loop_closure.h"
#include "mapping/pose_graph.h"
#include "tracking/tracker_options.h"

namespace fleetloc::mapping {

struct MapperOptions {
  RegistrationOptions registration;
  LoopClosureOptions loops;
  PoseGraphSolveOptions solve;
  tracking::OdometryNoiseOptions odometry;  // covariance of the odometry edges
  int sequential_neighbours = 2;            // frame k is registered against frames k-1 .. k-n
  double min_sequential_overlap = 0.3;      // predicted footprint overlap needed to try a pair
  double min_registered_fraction = 0.5;     // of successive pairs (k-1, k); fewer: bad input
};

// Flat range checks; InvalidInput naming the field.
Status Validate(const MapperOptions& options);

struct MapperInput {
  geometry::CameraModel camera;
  geometry::Pose2 initial_base_in_map;    // base_link in map at the first frame
  std::vector<double> frame_times_s;      // ascending
  std::vector<geometry::Pose2> odometry;  // base_link in odom at each frame's time
};

// Frame `index` as CV_8UC1 of the camera's size, or the reason it cannot be read.
using FrameLoader = std::function<Result<cv::Mat>(int index)>;
// One progress or summary line (registered k/n, loop closures, solver iterations).
using MapperLog = std::function<void(const std::string& line)>;

struct MappedRun {
  std::vector<geometry::Pose2> camera_in_map;  // solved camera_ground pose of each frame
  int pairs_tried = 0;                         // sequential pairs attempted
  int pairs_registered = 0;
  int successive_registered = 0;  // of the N-1 pairs (k-1, k)
  int odometry_bridges = 0;       // successive pairs linked by odometry only
  int loop_candidates = 0;
  int loop_registered = 0;    // loop-closure pairs registered (added to the graph)
  int loop_outside_gate = 0;  // of those, far from the chain's prediction (see min_corroborating)
  int loop_pruned = 0;        // removed again: inconsistent after solving, or uncorroborated
  std::vector<PoseGraphSolveSummary> solves;  // chain-only, with loops, after pruning
};

// Requires frame_times_s and odometry of equal size ≥ 2. InvalidInput naming the problem for
// non-finite input, options that fail Validate, or a run whose successive frames mostly fail to
// register (no overlap, no texture); the loader's own error for a frame that cannot be read.
Result<MappedRun> MapRun(const MapperInput& input, const FrameLoader& load_frame,
                         const MapperOptions& options, const MapperLog& log = {});

}  // namespace fleetloc::mapping
