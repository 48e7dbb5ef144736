// A recorded run (docs/formats.md) as vehicle input: odometry samples, frames and the forward/
// images merged in time order, either as fast as possible or paced to their recorded times.
#pragma once

#include <chrono>

#include "run_io/run.h"
#include "tracker_agent/vehicle_input.h"

namespace fleetloc::tracker_agent {

class ReplayInput : public VehicleInput {
 public:
  // `paced`: each event is released at its recorded time after the first (else at once).
  ReplayInput(run_io::Run run, bool paced);
  // On equal times: odometry first (a frame always finds the sample at its own time), then the
  // downward frame, then the forward image.
  Result<std::optional<InputEvent>> Next() override;
  const run_io::Run& run() const { return run_; }

 private:
  // The next event's kind and time, nullopt at the end.
  std::optional<std::pair<InputEvent::Kind, double>> Peek() const;
  Result<cv::Mat> ReadFrame(const run_io::FrameRef& ref) const;

  run_io::Run run_;
  Pacer pacer_;
  size_t next_odometry_ = 0, next_frame_ = 0, next_forward_ = 0;
};

}  // namespace fleetloc::tracker_agent
