// Vehicle streams: partitions and the writer-partition check.
#include "transport/vehicle_streams.h"

#include <algorithm>

#include "transport/topic_names.h"

namespace fleetloc::transport {

namespace {

std::string Join(const std::vector<std::string>& names) {
  if (names.empty()) return "the default partition";
  std::string joined;
  for (const std::string& name : names) joined += (joined.empty() ? "'" : ", '") + name + "'";
  return joined;
}

}  // namespace

Status CheckVehiclePartition(const std::string& vehicle_id,
                             const std::vector<std::string>& writer_partitions) {
  const std::string own = topics::VehiclePartition(vehicle_id);
  if (writer_partitions.size() == 1 && writer_partitions[0] == own) return Status::Ok();
  return InvalidInput("vehicle_id '" + vehicle_id + "' written in " + Join(writer_partitions) +
                      ", not in its own partition '" + own + "'");
}

Result<Entity> CreateVehiclePublisher(const Participant& participant,
                                      const std::string& vehicle_id) {
  return participant.CreatePublisher({topics::VehiclePartition(vehicle_id)});
}

Result<Entity> CreateAnyVehicleSubscriber(const Participant& participant) {
  return participant.CreateSubscriber({topics::kAnyVehiclePartition});
}

Status VehicleSourceCheck::Check(const std::string& vehicle_id, const dds_sample_info_t& info) {
  const WriterFacts* writer = writers_.Find(info.publication_handle);
  if (writer == nullptr) {
    return InvalidInput("vehicle_id '" + vehicle_id + "' from a writer that is not matched");
  }
  return CheckVehiclePartition(vehicle_id, writer->partitions);
}

}  // namespace fleetloc::transport
