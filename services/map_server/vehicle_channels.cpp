// Per-vehicle partitioned reply writers.
#include "map_server/vehicle_channels.h"

#include "transport/topic_names.h"

namespace fleetloc::map_server {

VehicleChannels::VehicleChannels(const transport::Participant& participant, std::string server_id,
                                 const transport::Topic<fleetloc_Tile>& tile_topic,
                                 const transport::Topic<fleetloc_PatchAck>& ack_topic,
                                 size_t max_vehicles)
    : participant_(participant),
      server_id_(std::move(server_id)),
      tile_topic_(tile_topic),
      ack_topic_(ack_topic),
      max_vehicles_(max_vehicles) {}

Result<std::unique_ptr<VehicleChannel>> VehicleChannels::Open(const std::string& vehicle_id) const {
  Result<transport::Entity> publisher =
      participant_.CreatePublisher({transport::topics::VehiclePartition(vehicle_id)});
  if (!publisher.ok()) return publisher.status();
  auto tiles =
      transport::Writer<fleetloc_Tile>::Create(publisher->get(), tile_topic_, transport::TileQos());
  if (!tiles.ok()) return tiles.status();
  auto acks = transport::Writer<fleetloc_PatchAck>::Create(
      publisher->get(), ack_topic_,
      transport::CommandQos().UserData(transport::topics::ServerIdUserData(server_id_)));
  if (!acks.ok()) return acks.status();
  return std::make_unique<VehicleChannel>(VehicleChannel{
      std::move(publisher).value(), std::move(tiles).value(), std::move(acks).value()});
}

Result<VehicleChannel*> VehicleChannels::Get(const std::string& vehicle_id) {
  if (auto it = channels_.find(vehicle_id); it != channels_.end()) {
    lru_.splice(lru_.begin(), lru_, it->second.second);
    return it->second.first.get();
  }
  Result<std::unique_ptr<VehicleChannel>> channel = Open(vehicle_id);
  if (!channel.ok()) return channel.status();
  lru_.push_front(vehicle_id);
  VehicleChannel* raw = channel->get();
  channels_.emplace(vehicle_id, std::make_pair(std::move(channel).value(), lru_.begin()));
  while (channels_.size() > max_vehicles_) {
    channels_.erase(lru_.back());
    lru_.pop_back();
  }
  return raw;
}

}  // namespace fleetloc::map_server
