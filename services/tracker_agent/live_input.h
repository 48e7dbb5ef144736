// A live vehicle as vehicle input: frames from a camera (its own thread, reopened when it fails
// or stalls) and ROS 2 odometry over DDS, both on the host clock, each checked: a camera that is
// gone, silent, or delivers frames of the wrong size; odometry that stops, goes back in time or is
// not finite — each a named issue in the agent's health and a log line when it starts and ends.
// Odometry whose clock went back for good (a restarted base controller) is taken as a new
// timeline after `odometry_stale_s` (kOdometryRestart first).
#pragma once

#include <atomic>
#include <condition_variable>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>

#include "camera_io/camera_source.h"
#include "run_io/run.h"
#include "timing/stream_watch.h"
#include "tracker_agent/agent_config.h"
#include "tracker_agent/ros_bridge.h"
#include "tracker_agent/vehicle_input.h"

namespace fleetloc::tracker_agent {

class LiveInput : public VehicleInput {
 public:
  using CameraOpener = std::function<Result<std::unique_ptr<camera_io::CameraSource>>()>;

  // Joins the DDS domain for the odometry and starts the camera thread (the first open may fail:
  // it is retried). `camera`: the camera.json the frames must fit (its size unless it is raw).
  static Result<std::unique_ptr<LiveInput>> Create(const AgentConfig& config,
                                                   const run_io::CameraFile& camera,
                                                   CameraOpener opener);
  // The opener of the configured source (aravis or gstreamer).
  static CameraOpener OpenerFor(const AgentConfig& config);
  ~LiveInput() override;

  // The next odometry sample or frame; kIdle after ~50 ms without either. Never ends.
  Result<std::optional<InputEvent>> Next() override;
  std::vector<InputIssue> Issues() const override;
  long long DroppedFrames() const override;
  std::optional<std::pair<double, geometry::Pose2>> LatestOdometry() const override {
    return latest_odometry_;
  }

 private:
  LiveInput(const AgentConfig& config, const run_io::CameraFile& camera, CameraOpener opener);
  void CameraLoop();
  // One frame from the camera thread: checked, queued (the oldest dropped when full).
  void Accept(camera_io::CapturedFrame frame);
  void DropFrame(const std::string& why, bool wrong_format);
  void TakeOdometry();
  void SetCameraError(const std::string& error);  // empty: available again

  LiveOptions options_;
  std::string vehicle_id_;
  cv::Size expected_size_;  // empty for a raw camera until its first frame
  CameraOpener opener_;
  std::unique_ptr<transport::Participant> participant_;
  std::unique_ptr<RosOdometryReader> odometry_;
  std::deque<InputEvent> ready_;  // odometry taken, not yet handed out (Next's thread only)
  std::optional<std::pair<double, geometry::Pose2>> latest_odometry_;
  timing::StreamWatch odometry_watch_;
  double odometry_bad_since_ = -1;  // host time of the first bad sample in a row (-1: none)
  bool odometry_was_stale_ = false;

  mutable std::mutex mutex_;  // guards what the camera thread shares
  std::condition_variable frame_ready_;
  std::deque<camera_io::CapturedFrame> frames_;
  timing::StreamWatch camera_watch_;
  std::string camera_error_;  // why the camera is unavailable (empty: it is open)
  std::string wrong_format_;  // the last wrong frame
  double wrong_format_host_s_ = -1e300;
  long long dropped_ = 0;                // frames dropped here (wrong size, queue full)
  double last_drop_log_ = 0;             // host time of the last log line about a camera drop
  camera_io::CameraStats camera_stats_;  // of the open camera, plus those closed before
  camera_io::CameraStats closed_stats_;
  mutable timing::CountWatch packet_loss_watch_;  // lost + resent packets (Issues() updates it)
  std::atomic<bool> stop_{false};
  std::thread camera_thread_;
  std::thread closer_;  // closes a camera the camera thread gave up on (one at a time)
};

}  // namespace fleetloc::tracker_agent
