// FleetListener: readers and their QoS.
#include "fleet_link/fleet_listener.h"

#include "transport/topic_names.h"
#include "transport/wire_util.h"

namespace fleetloc::fleet_link {

namespace topics = transport::topics;
using transport::Qos;
using transport::Reader;
using transport::Topic;
using transport::VehicleStreamReader;

Result<std::unique_ptr<FleetListener>> FleetListener::Create(const transport::Participant& p) {
  auto pose_topic = Topic<fleetloc_VehiclePose>::Create(p, topics::kVehiclePose);
  auto health_topic = Topic<fleetloc_VehicleHealth>::Create(p, topics::kVehicleHealth);
  auto service_topic = Topic<fleetloc_ServiceHealth>::Create(p, topics::kServiceHealth);
  if (!pose_topic.ok()) return pose_topic.status();
  if (!health_topic.ok()) return health_topic.status();
  if (!service_topic.ok()) return service_topic.status();
  // Only the newest sample of each vehicle matters (keep-last 1 per instance: a slow supervisor
  // skips superseded poses instead of queueing them). The pose reader requests a 3 s deadline,
  // compatible with the agents' PoseStreamQos (1 s offered); the health and service readers
  // request none, so a writer of any health period matches (as in transport::ServiceWatch).
  // No liveliness is requested (automatic, infinite): compatible with every writer's lease.
  // Poses and health come from every vehicle's partition, checked against it (vehicle_streams.h).
  auto poses = VehicleStreamReader<fleetloc_VehiclePose>::Create(
      p, *pose_topic, Qos().Reliable().Volatile().KeepLast(1).Deadline(3.0));
  auto health = VehicleStreamReader<fleetloc_VehicleHealth>::Create(
      p, *health_topic, Qos().Reliable().Volatile().KeepLast(1));
  auto services = Reader<fleetloc_ServiceHealth>::Create(p.get(), *service_topic,
                                                         Qos().Reliable().Volatile().KeepLast(1));
  if (!poses.ok()) return poses.status();
  if (!health.ok()) return health.status();
  if (!services.ok()) return services.status();
  return std::unique_ptr<FleetListener>(
      new FleetListener(std::move(pose_topic).value(), std::move(health_topic).value(),
                        std::move(service_topic).value(), std::move(poses).value(),
                        std::move(health).value(), std::move(services).value()));
}

Status FleetListener::Take(Received* out) {
  // Converts each sample with `convert`; adds (id, value) to `into` or the message to rejections.
  auto take = [&](auto& reader, auto convert, auto* into) -> Status {
    Result<int> taken = reader.TakeAll(
        [&](const auto& sample, const dds_sample_info_t&) {
          auto value = convert(sample);
          if (!value.ok()) return out->rejections.push_back(value.status().message());
          into->emplace_back(transport::GetBounded(sample.vehicle_id), std::move(value).value());
        },
        [&](const std::string& message) { out->rejections.push_back(message); });
    return taken.ok() ? Status::Ok() : taken.status();
  };
  FLEETLOC_RETURN_IF_ERROR(take(poses_, PoseFromIdl, &out->poses));
  FLEETLOC_RETURN_IF_ERROR(take(health_, HealthFromIdl, &out->health));
  Result<int> taken =
      services_.TakeAll([&](const fleetloc_ServiceHealth& sample, const dds_sample_info_t&) {
        Result<ServiceReport> report = ServiceFromIdl(sample);
        if (!report.ok()) return out->rejections.push_back(report.status().message());
        out->services.push_back(std::move(report).value());
      });
  return taken.ok() ? Status::Ok() : taken.status();
}

uint64_t FleetListener::DeadlineMisses() const {
  dds_requested_deadline_missed_status_t status{};
  if (dds_get_requested_deadline_missed_status(poses_.get(), &status) < 0) return 0;
  return status.total_count;
}

}  // namespace fleetloc::fleet_link
