// What a vehicle feeds its tracker agent: odometry samples, downward camera frames and
// forward-camera images, in time order,
// from a source behind this small interface (a recorded run, a live simulated vehicle, later a
// real camera and wheel odometry driver).
#pragma once

#include <chrono>
#include <opencv2/core.hpp>
#include <optional>

#include "base/status.h"
#include "geometry/pose2.h"

namespace fleetloc::tracker_agent {

struct InputEvent {
  // kForwardFrame: an image of the forward (landmark) camera (forward/, docs/formats.md).
  enum class Kind { kOdometry, kFrame, kForwardFrame };
  Kind kind = Kind::kOdometry;
  double t = 0.0;            // capture time, seconds (the source's clock)
  geometry::Pose2 odom;      // kOdometry: base_link in odom
  cv::Mat frame;             // kFrame: the camera image (raw or rectified, see camera.json);
                             // kForwardFrame: the forward camera's image as recorded
};

class VehicleInput {
 public:
  virtual ~VehicleInput() = default;
  // The next event; nullopt when the source has ended. A frame (of either camera) that cannot be
  // read is an error naming its file (the agent counts it as a dropped frame and goes on).
  virtual Result<std::optional<InputEvent>> Next() = 0;
};

// Releases events at their own times after the first one (live speed), or at once.
class Pacer {
 public:
  explicit Pacer(bool paced) : paced_(paced) {}
  // Sleeps until `t` seconds after the first time given, in wall-clock time (if paced).
  void WaitUntil(double t);

 private:
  bool paced_;
  std::optional<std::chrono::steady_clock::time_point> wall_start_;
  double t_start_ = 0.0;
};

}  // namespace fleetloc::tracker_agent
