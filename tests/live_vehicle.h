// The live simulated vehicle (tools/live_sim) for the live-camera agent tests: the same classes,
// failing the test instead of returning a Status.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "base/eventually.h"
#include "camera_io/camera_source.h"
#include "live_sim/live_vehicle_sim.h"
#include "tracker_agent/ros_bridge.h"
#include "transport/ros_messages.h"

namespace fleetloc::testing {

using live_sim::FakeGigECamera;
using live_sim::SleepUntilHost;

inline std::unique_ptr<live_sim::PlannedDrive> PlanDrive(const cv::Mat& floor, double resolution_m,
                                                         int frames, double rate_hz, double start_t,
                                                         double frame_delay_s, double speed_px_s,
                                                         uint64_t seed) {
  auto drive = live_sim::PlannedDrive::Create(floor, resolution_m, frames, rate_hz, start_t,
                                              frame_delay_s, speed_px_s, seed);
  if (!drive.ok()) {
    ADD_FAILURE() << drive.status().message();
    std::abort();
  }
  return std::move(drive).value();
}

// A drive of a 2 s lead (standing still) planned to start on the camera's 100 ms grid a few
// seconds ahead, time for an agent to start and match. Its frames are rendered in the planning; on
// a loaded host that took most of those seconds (CI under other load, session 54), and such a
// drive is planned again further ahead. Its start in *start_t.
inline std::unique_ptr<live_sim::PlannedDrive> PlanDriveAhead(const cv::Mat& floor,
                                                              double resolution_m, int frames,
                                                              uint64_t seed, double* start_t) {
  constexpr double kMinAheadS = 3.0;
  std::unique_ptr<live_sim::PlannedDrive> drive;
  for (double ahead_s = 4.0; !drive || *start_t - camera_io::HostNow() < kMinAheadS; ahead_s *= 2) {
    if (ahead_s > 40.0) {
      ADD_FAILURE() << "planning a drive takes longer than its lead";
      std::abort();
    }
    *start_t = std::ceil(camera_io::HostNow() + ahead_s);
    drive = PlanDrive(floor, resolution_m, frames, 10.0, *start_t, 2.0, 1000.0, seed);
  }
  return drive;
}

inline std::unique_ptr<live_sim::OdometryPublisher> PublishOdometry(
    const transport::Participant& p, const std::vector<geometry::StampedPose>& samples,
    live_sim::OdometryPublisher::Mangle mangle = nullptr, double min_gap_s = 0.0) {
  auto publisher = live_sim::OdometryPublisher::Create(p, samples, std::move(mangle), min_gap_s);
  if (!publisher.ok()) {
    ADD_FAILURE() << publisher.status().message();
    std::abort();
  }
  return std::move(publisher).value();
}

// A tracker agent's configuration for the fake GigE Vision camera on 127.0.0.1 (640×480 at 10 Hz),
// with its camera file, outbox and working files in `dir`.
inline nlohmann::json AravisAgentConfig(const std::string& vehicle_id, int domain,
                                        const std::filesystem::path& dir) {
  return {{"vehicle_id", vehicle_id},
          {"domain", domain},
          {"source", "aravis"},
          {"camera", (dir / "camera.json").string()},
          {"outbox", (dir / "outbox.db").string()},
          {"health_period_s", 0.2},
          {"drain_s", 0.0},
          {"aravis",
           {{"device", "127.0.0.1"},
            {"region", {0, 0, 640, 480}},
            {"frame_rate_hz", 10.0},
            {"packet_size", 8192}}}};
}

// The vehicle stack's side of the agent's ROS 2 pose topics (docs/topics.md): a reader of the
// poses the agent publishes and a writer of the start pose it takes.
struct RosPoseEndpoints {
  using PoseMsg = geometry_msgs_msg_dds__PoseWithCovarianceStamped_;
  explicit RosPoseEndpoints(const transport::Participant& p)
      : pose_topic(transport::Topic<PoseMsg>::Create(p, "rt/fleetloc/pose")),
        init_topic(transport::Topic<PoseMsg>::Create(p, "rt/initialpose")),
        poses(transport::Reader<PoseMsg>::Create(p.get(), *pose_topic,
                                                 tracker_agent::RosDefaultQos(1000))),
        initial_pose(transport::Writer<PoseMsg>::Create(p.get(), *init_topic,
                                                        tracker_agent::RosDefaultQos())) {}
  Result<transport::Topic<PoseMsg>> pose_topic, init_topic;
  Result<transport::Reader<PoseMsg>> poses;
  Result<transport::Writer<PoseMsg>> initial_pose;
};

}  // namespace fleetloc::testing
