// The vehicle side of tile streaming: announces nothing, asks the map server for tiles
// (TileRequest) and takes the answers from its own partition, plus the servers' MosaicInfo.
// Used by the tracker agent, the benchmarks and the integration tests.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "mosaic/tile_key.h"
#include "transport/tile_messages.h"
#include "transport/typed_io.h"
#include "transport/vehicle_streams.h"

namespace fleetloc::transport {

class TileClient {
 public:
  // `vehicle_id` must satisfy IsValidEntityId (InvalidInput otherwise).
  static Result<std::unique_ptr<TileClient>> Create(const Participant& participant,
                                                    const std::string& vehicle_id);

  // Sends one request for `tiles` (at most 256). `mosaic_id` empty: whatever the server serves.
  Status Request(uint32_t request_id, const std::string& mosaic_id,
                 const std::vector<mosaic::TileKey>& tiles);
  // The tiles received since the last call.
  Result<std::vector<ReceivedTile>> TakeTiles();
  // The newest MosaicInfo received from any server (kept until a newer one arrives).
  std::optional<fleetloc_MosaicInfo> LatestMosaicInfo();
  // The newest MosaicInfo of each server heard from, by server id (a mosaic split across servers
  // has one per server, each with the tile range it owns).
  const std::map<std::string, fleetloc_MosaicInfo>& MosaicInfos();

  // True when a map server reads our requests and our tile reader is matched by its writer.
  bool ServerMatched() const;
  bool RequestsMatched() const { return requests_.MatchedReaders() > 0; }
  dds_entity_t tile_reader() const { return tile_reader_.get(); }
  const std::string& vehicle_id() const { return vehicle_id_; }

 private:
  TileClient(std::string vehicle_id, Entity subscriber, Topic<fleetloc_TileRequest> request_topic,
             Topic<fleetloc_Tile> tile_topic, Topic<fleetloc_MosaicInfo> info_topic,
             VehicleStreamWriter<fleetloc_TileRequest> requests, Reader<fleetloc_Tile> tile_reader,
             Reader<fleetloc_MosaicInfo> info_reader);

  std::string vehicle_id_;
  Entity subscriber_;
  Topic<fleetloc_TileRequest> request_topic_;
  Topic<fleetloc_Tile> tile_topic_;
  Topic<fleetloc_MosaicInfo> info_topic_;
  VehicleStreamWriter<fleetloc_TileRequest> requests_;  // in the vehicle's partition
  Reader<fleetloc_Tile> tile_reader_;
  Reader<fleetloc_MosaicInfo> info_reader_;
  std::map<std::string, fleetloc_MosaicInfo> infos_;  // by server id
};

}  // namespace fleetloc::transport
