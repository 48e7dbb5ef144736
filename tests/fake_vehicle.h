// A vehicle as the supervisor sees it, for the supervisor's integration tests: publishes a pose
// and a health report like an agent, without tracking anything.
#pragma once

#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "transport/pose_messages.h"
#include "transport/topic_names.h"
#include "transport/vehicle_streams.h"
#include "transport/wire_util.h"

namespace fleetloc::testing {

// Publishes a vehicle's pose (at 20 Hz while Pump is called) and health like an agent.
class FakeVehicle {
 public:
  FakeVehicle(transport::Participant& p, std::string id) : id_(std::move(id)) {
    pose_topic_ = std::make_unique<transport::Topic<fleetloc_VehiclePose>>(
        std::move(transport::Topic<fleetloc_VehiclePose>::Create(p, transport::topics::kVehiclePose)
                      .value()));
    health_topic_ = std::make_unique<transport::Topic<fleetloc_VehicleHealth>>(std::move(
        transport::Topic<fleetloc_VehicleHealth>::Create(p, transport::topics::kVehicleHealth)
            .value()));
    poses_ = std::make_unique<transport::VehicleStreamWriter<fleetloc_VehiclePose>>(
        std::move(transport::VehicleStreamWriter<fleetloc_VehiclePose>::Create(
                      p, id_, *pose_topic_, transport::PoseStreamQos())
                      .value()));
    health_ = std::make_unique<transport::VehicleStreamWriter<fleetloc_VehicleHealth>>(
        std::move(transport::VehicleStreamWriter<fleetloc_VehicleHealth>::Create(
                      p, id_, *health_topic_, transport::PeriodicStateQos(3, 5))
                      .value()));
  }
  void Publish(double x, unsigned short wire_version = fleetloc_CURRENT_WIRE_VERSION) {
    transport::PoseReport report{
        id_, ToSeconds(transport::NowStamp()), {}, tracking::LockState::kTracking, 1};
    report.base_in_map.pose = {x, 0.25, 0.1};
    report.base_in_map.covariance = Eigen::Vector3d(1e-8, 1e-8, 1e-6).asDiagonal();
    fleetloc_VehiclePose pose = transport::ToIdl(report);
    pose.wire_version = wire_version;
    ASSERT_TRUE(poses_->Write(pose).ok());
    fleetloc_VehicleHealth health{};
    health.wire_version = wire_version;
    transport::SetBounded(health.vehicle_id, id_);
    health.stamp = transport::NowStamp();
    health.cycle_ms_p95 = 2.5f;
    health.inliers = 24;
    health.map_server_reachable = true;
    ASSERT_TRUE(health_->Write(health).ok());
  }

 private:
  static double ToSeconds(const fleetloc_TimeStamp& s) { return transport::ToSeconds(s); }
  std::string id_;
  std::unique_ptr<transport::Topic<fleetloc_VehiclePose>> pose_topic_;
  std::unique_ptr<transport::Topic<fleetloc_VehicleHealth>> health_topic_;
  std::unique_ptr<transport::VehicleStreamWriter<fleetloc_VehiclePose>> poses_;
  std::unique_ptr<transport::VehicleStreamWriter<fleetloc_VehicleHealth>> health_;
};

}  // namespace fleetloc::testing
