// A live simulated vehicle as vehicle input: frames rendered from a floor image along the
// simulator's route (camera effects, wheel-odometry errors), in real time or as fast as possible,
// forever — when one planned stretch of route ends, the next continues from where it left off
// (same route position, time and odometry pose).
#pragma once

#include <chrono>
#include <deque>
#include <memory>
#include <optional>

#include "mosaic/raster_source.h"
#include "sim/run_simulator.h"
#include "tracker_agent/vehicle_input.h"

namespace fleetloc::tracker_agent {

class SimInput : public VehicleInput {
 public:
  // `floor` (level 0 of the floor the vehicle drives on) must outlive the input. `options` plans
  // each stretch (its timing.frames is the stretch length). InvalidInput for options the
  // simulator rejects or a floor too small for the route.
  static Result<std::unique_ptr<SimInput>> Create(mosaic::RasterSource* floor,
                                                  const geometry::CameraModel& camera,
                                                  const sim::SimOptions& options, bool paced);

  Result<std::optional<InputEvent>> Next() override;
  // base_link in map at the first frame, perturbed as run.json's initial_pose would be.
  geometry::PoseWithCovariance initial_pose() const;
  // The simulator's truth at time t (for tests and the demo's error display).
  geometry::Pose2 TruthAt(double t) const { return simulator_->TruthAt(t); }

 private:
  SimInput(mosaic::RasterSource* floor, const geometry::CameraModel& camera,
           const sim::SimOptions& options, bool paced)
      : floor_(floor), camera_(camera), options_(options), pacer_(paced) {}
  // Plans the next stretch starting at time `t0` with odometry pose `odom0` (first: from options).
  Status PlanStretch(std::optional<std::pair<double, geometry::Pose2>> from);

  mosaic::RasterSource* floor_;
  geometry::CameraModel camera_;
  sim::SimOptions options_;
  Pacer pacer_;
  std::unique_ptr<sim::RunSimulator> simulator_;
  geometry::PoseWithCovariance initial_;
  size_t next_odometry_ = 0;
  int next_frame_ = 0;
};

}  // namespace fleetloc::tracker_agent
