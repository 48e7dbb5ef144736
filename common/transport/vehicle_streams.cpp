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

void VehicleSourceCheck::LearnNewWriters() {
  dds_subscription_matched_status_t status{};
  if (dds_get_subscription_matched_status(reader_, &status) < 0) return;
  if (status.total_count == matched_total_) return;
  matched_total_ = status.total_count;
  std::vector<dds_instance_handle_t> writers(status.current_count + 16);
  const dds_return_t n = dds_get_matched_publications(reader_, writers.data(), writers.size());
  for (dds_return_t i = 0; i < std::min<dds_return_t>(n, static_cast<dds_return_t>(writers.size()));
       ++i) {
    (void)WriterPartitions(writers[i]);
  }
}

Status VehicleSourceCheck::Check(const std::string& vehicle_id, const dds_sample_info_t& info) {
  const std::vector<std::string>* partitions = WriterPartitions(info.publication_handle);
  if (partitions == nullptr) {
    return InvalidInput("vehicle_id '" + vehicle_id + "' from a writer that is not matched");
  }
  return CheckVehiclePartition(vehicle_id, *partitions);
}

const std::vector<std::string>* VehicleSourceCheck::WriterPartitions(dds_instance_handle_t writer) {
  if (auto it = partitions_.find(writer); it != partitions_.end()) return &it->second;
  dds_builtintopic_endpoint_t* endpoint = dds_get_matched_publication_data(reader_, writer);
  if (endpoint == nullptr) return nullptr;
  std::vector<std::string> names;
  uint32_t n = 0;
  char** raw = nullptr;
  if (endpoint->qos != nullptr && dds_qget_partition(endpoint->qos, &n, &raw)) {
    for (uint32_t i = 0; i < n; ++i) {
      names.emplace_back(raw[i]);
      dds_free(raw[i]);
    }
    dds_free(raw);
  }
  dds_builtintopic_free_endpoint(endpoint);
  if (partitions_.size() >= kMaxWriters) partitions_.clear();
  return &partitions_.emplace(writer, std::move(names)).first->second;
}

}  // namespace fleetloc::transport
