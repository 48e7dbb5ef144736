// TileRequest → Tile replies in the vehicle's partition.
#include "map_server/tile_service.h"

#include <spdlog/spdlog.h>

#include "transport/mosaic_messages.h"
#include "transport/tile_messages.h"
#include "transport/wire_util.h"

namespace fleetloc::map_server {

using transport::GetBounded;

std::vector<std::string> TileService::CounterNames() {
  return {"tile_requests",         "tiles_served",        "tile_bytes_served",
          "rejected_tile_request", "rejected_tile_range", "rejected_unknown_mosaic",
          "tiles_not_found",       "tile_read_errors",    "tile_requests_unmatched",
          "tiles_not_owned"};
}

TileService::TileService(mosaic::TileStore* store, mosaic::TileOwnership owned,
                         VehicleChannels* channels, ServerCounters* counters,
                         int max_tiles_per_request, size_t cache_bytes)
    : store_(store),
      owned_(owned),
      channels_(channels),
      counters_(counters),
      max_tiles_per_request_(max_tiles_per_request),
      cache_(cache_bytes) {}

void TileService::Receive(const fleetloc_TileRequest& sample) {
  counters_->Add("tile_requests");
  const std::string vehicle_id = GetBounded(sample.vehicle_id);
  if (sample.wire_version != fleetloc_CURRENT_WIRE_VERSION) {
    counters_->Reject("rejected_tile_request", "TileRequest from '" + vehicle_id +
                                                   "': unknown wire_version " +
                                                   std::to_string(sample.wire_version));
    return;
  }
  if (!transport::IsValidEntityId(vehicle_id)) {
    counters_->Reject("rejected_tile_request",
                      "TileRequest: vehicle_id '" + vehicle_id + "' is not 1-11 of [A-Za-z0-9_-]");
    return;
  }
  if (static_cast<int>(sample.tiles._length) > max_tiles_per_request_) {
    counters_->Reject("rejected_tile_request", "TileRequest from '" + vehicle_id +
                                                   "': " + std::to_string(sample.tiles._length) +
                                                   " tiles, more than " +
                                                   std::to_string(max_tiles_per_request_));
    return;
  }
  transport::TileAsk ask = transport::FromIdl(sample);
  Request request{vehicle_id, ask.request_id, std::move(ask.mosaic_id), std::move(ask.tiles),
                  std::chrono::steady_clock::now()};
  pending_.Push(vehicle_id, std::move(request));
}

void TileService::AnswerPending(std::chrono::steady_clock::duration match_timeout) {
  auto channel = [this](const std::string& vehicle_id) -> VehicleChannel* {
    Result<VehicleChannel*> opened = channels_->Get(vehicle_id);
    if (opened.ok()) return *opened;
    counters_->Reject("tile_read_errors", opened.status().message());
    return nullptr;
  };
  pending_.Flush(
      [&](const std::string& vehicle) {
        VehicleChannel* c = channel(vehicle);
        return c != nullptr && c->tiles.MatchedReaders() > 0;
      },
      [&](const std::string& vehicle, const Request& request) {
        Answer(request, *channel(vehicle));
      },
      [&](const std::string& vehicle, const Request& request) {
        counters_->Reject("tile_requests_unmatched",
                          "TileRequest " + std::to_string(request.request_id) + " from '" +
                              vehicle + "': no tile reader of that vehicle matched");
      },
      match_timeout);
}

void TileService::Answer(const Request& request, VehicleChannel& channel) {
  for (const mosaic::TileKey& key : request.tiles) {
    if (transport::InGrid(store_->layout(), key) && !owned_.Owns(key)) {
      counters_->Add("tiles_not_owned");  // another map server answers for it
      continue;
    }
    mosaic::TilePtr bytes;
    const fleetloc_Tile tile = Reply(request, key, &bytes);
    if (Status written = channel.tiles.Write(tile); !written.ok()) {
      counters_->Reject("tile_read_errors", written.message());
      continue;
    }
    if (tile.status == fleetloc_TILE_OK) {
      counters_->Add("tiles_served");
      counters_->Add("tile_bytes_served", bytes->total());
    }
  }
  reply_latency_.Observe(
      std::chrono::duration<double>(std::chrono::steady_clock::now() - request.received).count());
}

Result<mosaic::TilePtr> TileService::EncodedTile(const mosaic::TileKey& key) {
  if (mosaic::TilePtr cached = cache_.Get(key)) return cached;
  Result<std::vector<std::uint8_t>> read = store_->ReadTileBytes(key);
  if (!read.ok()) return read.status();
  auto encoded = std::make_shared<const cv::Mat>(
      cv::Mat(1, static_cast<int>(read->size()), CV_8U, read->data()).clone());
  cache_.Put(key, encoded);
  return mosaic::TilePtr(encoded);
}

fleetloc_Tile TileService::Reply(const Request& request, const mosaic::TileKey& key,
                                 mosaic::TilePtr* bytes) {
  const mosaic::MosaicLayout layout = store_->layout();
  transport::TileAnswer tile{request.vehicle_id, request.request_id, key, layout.mosaic_id,
                             layout.version};
  const std::string what = "tile " + mosaic::ToString(key) + " for '" + request.vehicle_id + "'";
  if (!request.mosaic_id.empty() && request.mosaic_id != layout.mosaic_id) {
    tile.status = fleetloc_TILE_UNKNOWN_MOSAIC;
    counters_->Reject("rejected_unknown_mosaic",
                      what + ": unknown mosaic '" + request.mosaic_id + "'");
  } else if (!transport::InGrid(layout, key)) {
    tile.status = fleetloc_TILE_OUT_OF_RANGE;
    counters_->Reject("rejected_tile_range", what + ": outside the mosaic's tile grid");
  } else if (Result<mosaic::TilePtr> read = EncodedTile(key); read.ok()) {
    *bytes = std::move(read).value();
    tile.status = fleetloc_TILE_OK;
    tile.data = {(*bytes)->data, (*bytes)->total()};
  } else if (read.status().code() == StatusCode::kNotFound) {
    tile.status = fleetloc_TILE_NOT_FOUND;  // a tile never written: blank floor, not an error
    counters_->Add("tiles_not_found");
  } else {
    tile.status = fleetloc_TILE_ERROR;
    counters_->Reject("tile_read_errors", what + ": " + read.status().message());
  }
  if (tile.status != fleetloc_TILE_OK && tile.status != fleetloc_TILE_NOT_FOUND) {
    tile.error = counters_->last_error();
  }
  return transport::ToIdl(tile);
}

}  // namespace fleetloc::map_server
