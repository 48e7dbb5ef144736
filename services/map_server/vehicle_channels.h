// Per-vehicle reply channels of the map server: a publisher in the vehicle's own partition with
// its Tile and PatchAck writers, created on the vehicle's first request, so that replies reach
// only that vehicle (per-vehicle traffic does not grow with the fleet). Bounded: the least
// recently used channel is closed past `max_vehicles`.
#pragma once

#include <list>
#include <memory>
#include <string>
#include <unordered_map>

#include "transport/typed_io.h"

namespace fleetloc::map_server {

// A writer's replies are lost until the vehicle's reader is matched: callers check
// MatchedReaders() on the writer they use and hold replies back until then.
struct VehicleChannel {
  transport::Entity publisher;
  transport::Writer<fleetloc_Tile> tiles;
  transport::Writer<fleetloc_PatchAck> acks;
};

class VehicleChannels {
 public:
  // `server_id` goes in the USER_DATA of the PatchAck writers (topics::ServerIdUserData).
  VehicleChannels(const transport::Participant& participant, std::string server_id,
                  const transport::Topic<fleetloc_Tile>& tile_topic,
                  const transport::Topic<fleetloc_PatchAck>& ack_topic, size_t max_vehicles);

  // The channel of `vehicle_id` (must satisfy transport::IsValidEntityId), created if needed.
  Result<VehicleChannel*> Get(const std::string& vehicle_id);
  size_t size() const { return channels_.size(); }

 private:
  Result<std::unique_ptr<VehicleChannel>> Open(const std::string& vehicle_id) const;

  const transport::Participant& participant_;
  const std::string server_id_;
  const transport::Topic<fleetloc_Tile>& tile_topic_;
  const transport::Topic<fleetloc_PatchAck>& ack_topic_;
  const size_t max_vehicles_;
  std::list<std::string> lru_;  // most recent first
  std::unordered_map<std::string,
                     std::pair<std::unique_ptr<VehicleChannel>, std::list<std::string>::iterator>>
      channels_;
};

}  // namespace fleetloc::map_server
