// Stretch after stretch of simulated driving.
#include "tracker_agent/sim_input.h"

#include <cmath>

namespace fleetloc::tracker_agent {

Result<std::unique_ptr<SimInput>> SimInput::Create(mosaic::RasterSource* floor,
                                                   const geometry::CameraModel& camera,
                                                   const sim::SimOptions& options, bool paced) {
  std::unique_ptr<SimInput> input(new SimInput(floor, camera, options, paced));
  FLEETLOC_RETURN_IF_ERROR(input->PlanStretch(std::nullopt));
  const Eigen::Vector3d sigma = input->simulator_->initial_sigma();
  input->initial_ = {input->simulator_->initial_pose(), sigma.cwiseProduct(sigma).asDiagonal()};
  return input;
}

geometry::PoseWithCovariance SimInput::initial_pose() const { return initial_; }

Status SimInput::PlanStretch(std::optional<std::pair<double, geometry::Pose2>> from) {
  sim::SimOptions o = options_;
  if (from) {
    // Continue at the last odometry sample: same time, same odometry pose, same route position.
    const auto [t0, odom0] = *from;
    const sim::Route& route = simulator_->route();
    const double s = route.ArcLengthAt(t0 - o.timing.start_time_s) / route.length_m();
    o.route.start_fraction = s - std::floor(s);
    o.timing.start_time_s = t0;
    o.odometry.start_pose = odom0;
    o.seed = options_.seed + 7919;  // fresh noise for the new stretch
  }
  Result<std::unique_ptr<sim::RunSimulator>> planned =
      sim::RunSimulator::Create(floor_, camera_, o);
  if (!planned.ok()) return planned.status();
  options_ = o;
  simulator_ = std::move(planned).value();
  next_odometry_ = from ? 1 : 0;  // the first sample repeats the last one of the stretch before
  next_frame_ = 0;
  return Status::Ok();
}

Result<std::optional<InputEvent>> SimInput::Next() {
  const auto& odometry = simulator_->odometry();
  const auto& truth = simulator_->truth();
  if (next_odometry_ >= odometry.size() && next_frame_ >= static_cast<int>(truth.size())) {
    FLEETLOC_RETURN_IF_ERROR(PlanStretch(std::make_pair(odometry.back().t, odometry.back().pose)));
    return Next();
  }
  const bool take_odometry =
      next_odometry_ < odometry.size() && (next_frame_ >= static_cast<int>(truth.size()) ||
                                           odometry[next_odometry_].t <= truth[next_frame_].t);
  InputEvent event;
  if (take_odometry) {
    event.kind = InputEvent::Kind::kOdometry;
    event.t = odometry[next_odometry_].t;
    event.odom = odometry[next_odometry_].pose;
    ++next_odometry_;
  } else {
    event.kind = InputEvent::Kind::kFrame;
    event.t = truth[next_frame_].t;
    event.frame = simulator_->RenderFrame(next_frame_++).image;
  }
  pacer_.WaitUntil(event.t);
  return std::optional<InputEvent>(std::move(event));
}

}  // namespace fleetloc::tracker_agent
