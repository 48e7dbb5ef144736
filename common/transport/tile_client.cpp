// Tile requests and partitioned tile replies, vehicle side.
#include "transport/tile_client.h"

#include "transport/topic_names.h"
#include "transport/wire_util.h"

namespace fleetloc::transport {

TileClient::TileClient(std::string vehicle_id, Entity subscriber,
                       Topic<fleetloc_TileRequest> request_topic, Topic<fleetloc_Tile> tile_topic,
                       Topic<fleetloc_MosaicInfo> info_topic,
                       VehicleStreamWriter<fleetloc_TileRequest> requests,
                       Reader<fleetloc_Tile> tile_reader, Reader<fleetloc_MosaicInfo> info_reader)
    : vehicle_id_(std::move(vehicle_id)),
      subscriber_(std::move(subscriber)),
      request_topic_(std::move(request_topic)),
      tile_topic_(std::move(tile_topic)),
      info_topic_(std::move(info_topic)),
      requests_(std::move(requests)),
      tile_reader_(std::move(tile_reader)),
      info_reader_(std::move(info_reader)) {}

Result<std::unique_ptr<TileClient>> TileClient::Create(const Participant& participant,
                                                       const std::string& vehicle_id) {
  if (!IsValidEntityId(vehicle_id)) {
    return InvalidInput("vehicle id '" + vehicle_id + "' is not 1-11 of [A-Za-z0-9_-]");
  }
  auto request_topic = Topic<fleetloc_TileRequest>::Create(participant, topics::kTileRequest);
  auto tile_topic = Topic<fleetloc_Tile>::Create(participant, topics::kTile);
  auto info_topic = Topic<fleetloc_MosaicInfo>::Create(participant, topics::kMosaicInfo);
  if (!request_topic.ok()) return request_topic.status();
  if (!tile_topic.ok()) return tile_topic.status();
  if (!info_topic.ok()) return info_topic.status();
  auto subscriber = participant.CreateSubscriber({topics::VehiclePartition(vehicle_id)});
  if (!subscriber.ok()) return subscriber.status();
  auto requests = VehicleStreamWriter<fleetloc_TileRequest>::Create(participant, vehicle_id,
                                                                    *request_topic, CommandQos());
  auto tiles = Reader<fleetloc_Tile>::Create(subscriber->get(), *tile_topic, TileQos());
  auto info =
      Reader<fleetloc_MosaicInfo>::Create(participant.get(), *info_topic, DurableStateQos());
  if (!requests.ok()) return requests.status();
  if (!tiles.ok()) return tiles.status();
  if (!info.ok()) return info.status();
  return std::unique_ptr<TileClient>(new TileClient(
      vehicle_id, std::move(subscriber).value(), std::move(request_topic).value(),
      std::move(tile_topic).value(), std::move(info_topic).value(), std::move(requests).value(),
      std::move(tiles).value(), std::move(info).value()));
}

Status TileClient::Request(uint32_t request_id, const std::string& mosaic_id,
                           const std::vector<mosaic::TileKey>& tiles) {
  if (tiles.size() > 256) return InvalidInput("a tile request holds at most 256 tiles");
  std::vector<fleetloc_TileAddress> addresses;
  const fleetloc_TileRequest request =
      ToIdl(TileAsk{vehicle_id_, request_id, mosaic_id, tiles}, &addresses);
  return requests_.Write(request);
}

Result<std::vector<ReceivedTile>> TileClient::TakeTiles() {
  std::vector<ReceivedTile> received;
  Result<int> taken = tile_reader_.TakeAll(
      [&](const fleetloc_Tile& t, const dds_sample_info_t&) { received.push_back(FromIdl(t)); });
  if (!taken.ok()) return taken.status();
  return received;
}

const std::map<std::string, fleetloc_MosaicInfo>& TileClient::MosaicInfos() {
  (void)info_reader_.TakeAll([&](const fleetloc_MosaicInfo& info, const dds_sample_info_t&) {
    fleetloc_MosaicInfo& kept = infos_[GetBounded(info.server_id)];
    if (info.version >= kept.version) kept = info;
  });
  return infos_;
}

std::optional<fleetloc_MosaicInfo> TileClient::LatestMosaicInfo() {
  std::optional<fleetloc_MosaicInfo> latest;
  for (const auto& [server, info] : MosaicInfos()) {
    if (!latest || info.version > latest->version) latest = info;
  }
  return latest;
}

bool TileClient::ServerMatched() const {
  return requests_.MatchedReaders() > 0 && tile_reader_.MatchedWriters() > 0;
}

}  // namespace fleetloc::transport
