// What a vehicle feeds its tracker agent: odometry samples, downward camera frames and
// forward-camera images, in time order,
// from a source behind this small interface (a recorded run, a live simulated vehicle, later a
// real camera and wheel odometry driver).
#pragma once

#include <chrono>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "base/status.h"
#include "geometry/pose2.h"

namespace fleetloc::tracker_agent {

struct InputEvent {
  // kForwardFrame: an image of the forward (landmark) camera (forward/, docs/formats.md).
  // kIdle: nothing arrived for a moment (live sources); the agent does its housekeeping and asks
  // again. kOdometryRestart: the odometry source started a new timeline (its clock went back for
  // good); the agent forgets the old history before the odometry that follows.
  enum class Kind { kOdometry, kFrame, kForwardFrame, kIdle, kOdometryRestart };
  Kind kind = Kind::kOdometry;
  double t = 0.0;        // capture time, seconds (the source's clock)
  geometry::Pose2 odom;  // kOdometry: base_link in odom
  cv::Mat frame;         // kFrame: the camera image (raw or rectified, see camera.json);
                         // kForwardFrame: the forward camera's image as recorded
  // Live sources, kFrame (host clock, 0 otherwise): when the frame's buffer reached the process
  // and when Next handed it out (the agent's capture -> pose latency stages).
  double arrival_t = 0.0;
  double taken_t = 0.0;
};

// A problem with the input a live source sees (camera gone, odometry stale, ...), for health.
struct InputIssue {
  std::string name;    // e.g. "camera_stalled"
  bool error = false;  // ERROR (else WARN)
  std::string message;
};

class VehicleInput {
 public:
  virtual ~VehicleInput() = default;
  // The input's current problems (none for recorded and simulated inputs).
  virtual std::vector<InputIssue> Issues() const { return {}; }
  // Frames the source lost before they reached the agent (incomplete buffers, wrong sizes, ...).
  virtual long long DroppedFrames() const { return 0; }
  // The latest odometry the source has seen (base_link in odom, its time): the anchor for a start
  // pose that arrives between samples. nullopt when the source cannot tell.
  virtual std::optional<std::pair<double, geometry::Pose2>> LatestOdometry() const {
    return std::nullopt;
  }
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
