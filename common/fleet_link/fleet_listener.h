// The fleet's DDS readers (the supervisor's and `fleetctl status`'s): every vehicle's VehiclePose
// and VehicleHealth and every service's ServiceHealth, converted and checked (fleet_messages.h; a
// vehicle's samples also against their writer's partition, transport/vehicle_streams.h). Samples
// that fail the checks are returned as rejection messages for the caller to count or log.
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "fleet/vehicle_samples.h"
#include "fleet_link/fleet_messages.h"
#include "transport/typed_io.h"
#include "transport/vehicle_streams.h"

namespace fleetloc::fleet_link {

struct Received {
  std::vector<std::pair<std::string, fleet::PoseSample>> poses;
  std::vector<std::pair<std::string, fleet::HealthSample>> health;
  std::vector<ServiceReport> services;
  std::vector<std::string> rejections;
};

class FleetListener {
 public:
  static Result<std::unique_ptr<FleetListener>> Create(const transport::Participant& participant);

  // Appends everything received since the last call to *out. Internal on a DDS failure.
  Status Take(Received* out);
  // Requested-deadline-missed events of the pose reader so far (a vehicle silent for longer
  // than the reader's deadline counts once per missed period; a cross-check of the per-vehicle
  // last-seen timeout, see fleet/fleet_state.h).
  uint64_t DeadlineMisses() const;
  dds_entity_t pose_reader() const { return poses_.get(); }
  dds_entity_t health_reader() const { return health_.get(); }

 private:
  FleetListener(transport::Topic<fleetloc_VehiclePose> pose_topic,
                transport::Topic<fleetloc_VehicleHealth> health_topic,
                transport::Topic<fleetloc_ServiceHealth> service_topic,
                transport::VehicleStreamReader<fleetloc_VehiclePose> poses,
                transport::VehicleStreamReader<fleetloc_VehicleHealth> health,
                transport::Reader<fleetloc_ServiceHealth> services)
      : pose_topic_(std::move(pose_topic)),
        health_topic_(std::move(health_topic)),
        service_topic_(std::move(service_topic)),
        poses_(std::move(poses)),
        health_(std::move(health)),
        services_(std::move(services)) {}

  transport::Topic<fleetloc_VehiclePose> pose_topic_;
  transport::Topic<fleetloc_VehicleHealth> health_topic_;
  transport::Topic<fleetloc_ServiceHealth> service_topic_;
  transport::VehicleStreamReader<fleetloc_VehiclePose> poses_;
  transport::VehicleStreamReader<fleetloc_VehicleHealth> health_;
  transport::Reader<fleetloc_ServiceHealth> services_;
};

}  // namespace fleetloc::fleet_link
