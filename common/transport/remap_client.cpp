// RemapCommand out, RemapStatus in.
#include "transport/remap_client.h"

#include <cmath>
#include <random>

#include "transport/topic_names.h"
#include "transport/wire_util.h"

namespace fleetloc::transport {

Result<std::unique_ptr<RemapClient>> RemapClient::Create(const Participant& participant) {
  auto command_topic = Topic<fleetloc_RemapCommand>::Create(participant, topics::kRemapCommand);
  auto status_topic = Topic<fleetloc_RemapStatus>::Create(participant, topics::kRemapStatus);
  if (!command_topic.ok()) return command_topic.status();
  if (!status_topic.ok()) return status_topic.status();
  auto writer =
      Writer<fleetloc_RemapCommand>::Create(participant.get(), *command_topic, CommandQos());
  // Every map server writes a command's statuses in the same instance (keyed by command_id), and
  // split servers finish within moments of each other: a deep history keeps each server's final
  // status until it is taken, where depth 1 would keep only the last server's.
  constexpr int kStatusDepth = 64;
  auto reader = Reader<fleetloc_RemapStatus>::Create(participant.get(), *status_topic,
                                                     DurableStateQos(kStatusDepth));
  auto info_topic = Topic<fleetloc_MosaicInfo>::Create(participant, topics::kMosaicInfo);
  if (!writer.ok()) return writer.status();
  if (!reader.ok()) return reader.status();
  if (!info_topic.ok()) return info_topic.status();
  auto infos =
      Reader<fleetloc_MosaicInfo>::Create(participant.get(), *info_topic, DurableStateQos());
  if (!infos.ok()) return infos.status();
  return std::unique_ptr<RemapClient>(new RemapClient(
      std::move(command_topic).value(), std::move(status_topic).value(), std::move(writer).value(),
      std::move(reader).value(), std::move(info_topic).value(), std::move(infos).value()));
}

std::vector<std::string> RemapClient::ServersOf(const std::string& mosaic_id) {
  (void)infos_.TakeAll([&](const fleetloc_MosaicInfo& info, const dds_sample_info_t&) {
    mosaic_of_server_[GetBounded(info.server_id)] = GetBounded(info.mosaic_id);
  });
  std::vector<std::string> servers;
  for (const auto& [server, mosaic] : mosaic_of_server_) {
    if (mosaic_id.empty() || mosaic == mosaic_id) servers.push_back(server);
  }
  return servers;
}

Result<uint64_t> RemapClient::Send(const RemapRequest& r) {
  for (double v : {r.x_min, r.y_min, r.x_max, r.y_max}) {
    if (!std::isfinite(v)) return InvalidInput("remap region: coordinates must be finite numbers");
  }
  if (!(r.x_min < r.x_max && r.y_min < r.y_max)) {
    return InvalidInput("remap region: need x_min < x_max and y_min < y_max");
  }
  std::random_device random;
  const uint64_t id = (static_cast<uint64_t>(random()) << 32) | random();
  FLEETLOC_RETURN_IF_ERROR(SendRaw(ToIdl(r, id)));
  return id;
}

Status RemapClient::SendRaw(const fleetloc_RemapCommand& command) {
  return commands_.Write(command);
}

Result<std::vector<RemapProgress>> RemapClient::TakeStatuses() {
  std::vector<RemapProgress> statuses;
  Result<int> taken =
      statuses_.TakeAll([&](const fleetloc_RemapStatus& s, const dds_sample_info_t&) {
        statuses.push_back(FromIdl(s));
      });
  if (!taken.ok()) return taken.status();
  return statuses;
}

}  // namespace fleetloc::transport
