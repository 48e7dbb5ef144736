// A simulated forward-camera drive down the corridor: the weaving route (base_link in map), frame
// and odometry times, and drifting wheel odometry, for an end-to-end test of the global position
// update (landmark detection → map fit → pose correction). Rendering is ForwardRenderer's.
#pragma once

#include <cstdint>
#include <vector>

#include "base/status.h"
#include "geometry/camera_model.h"
#include "geometry/pose2.h"
#include "sim/corridor_scene.h"
#include "sim/sim_options.h"

namespace fleetloc::sim {

struct ForwardRunOptions {
  int frames = 40;
  double frame_rate_hz = 2.0;
  double odometry_rate_hz = 20.0;
  double speed_m_s = 0.4;
  double start_x_m = 0.8;          // along the corridor's axis (y = 0)
  double weave_amplitude_m = 0.3;  // y = amplitude · sin(2π x / wavelength)
  double weave_wavelength_m = 6.0;
  CorridorSceneOptions scene;
  OdometryOptions odometry;  // its own defaults: 1 % scale errors, 0.2°/s heading drift
  std::uint64_t seed = 1;    // odometry noise and per-frame rendering noise
};

// InvalidInput naming the field; also when the drive would leave the corridor (it must end at
// least 2 m before the end wall).
Status Validate(const ForwardRunOptions& options);

// base_link in map at time t (t = 0 at the first frame).
geometry::Pose2 ForwardRoutePose(const ForwardRunOptions& options, double t);

struct ForwardRunPlan {
  std::vector<geometry::StampedPose> frame_truth;  // base_link in map at each frame
  std::vector<geometry::StampedPose> odometry;     // base_link in odom, odometry_rate_hz, drifting
};

// The frame times and truth and the odometry over the same span (from the first to the last
// frame). The options must be valid (checked).
ForwardRunPlan PlanForwardRun(const ForwardRunOptions& options);

}  // namespace fleetloc::sim
