// TileRequest and Tile to and from plain values.
#include "transport/tile_messages.h"

#include "transport/mosaic_messages.h"
#include "transport/wire_util.h"

namespace fleetloc::transport {

fleetloc_TileRequest ToIdl(const TileAsk& ask, std::vector<fleetloc_TileAddress>* addresses) {
  addresses->clear();
  for (const mosaic::TileKey& key : ask.tiles) addresses->push_back(ToIdl(key));
  fleetloc_TileRequest request{};
  request.wire_version = fleetloc_CURRENT_WIRE_VERSION;
  SetBounded(request.vehicle_id, ask.vehicle_id);
  request.request_id = ask.request_id;
  SetBounded(request.mosaic_id, ask.mosaic_id);
  request.tiles._buffer = addresses->data();
  request.tiles._length = request.tiles._maximum = static_cast<uint32_t>(addresses->size());
  request.tiles._release = false;
  return request;
}

TileAsk FromIdl(const fleetloc_TileRequest& request) {
  TileAsk ask{
      GetBounded(request.vehicle_id), request.request_id, GetBounded(request.mosaic_id), {}};
  for (uint32_t i = 0; i < request.tiles._length; ++i) {
    ask.tiles.push_back(FromIdl(request.tiles._buffer[i]));
  }
  return ask;
}

fleetloc_Tile ToIdl(const TileAnswer& answer) {
  fleetloc_Tile tile{};
  tile.wire_version = fleetloc_CURRENT_WIRE_VERSION;
  tile.level = static_cast<uint16_t>(answer.key.level);
  tile.col = answer.key.col;
  tile.row = answer.key.row;
  SetBounded(tile.vehicle_id, answer.vehicle_id);
  tile.request_id = answer.request_id;
  SetBounded(tile.mosaic_id, answer.mosaic_id);
  tile.version = answer.version;
  tile.status = answer.status;
  SetBounded(tile.error, answer.error);
  tile.data = BorrowOctets(answer.data);
  return tile;
}

ReceivedTile FromIdl(const fleetloc_Tile& t) {
  ReceivedTile tile;
  tile.key = {t.level, t.col, t.row};
  tile.request_id = t.request_id;
  tile.status = t.status;
  tile.version = t.version;
  tile.mosaic_id = GetBounded(t.mosaic_id);
  tile.error = GetBounded(t.error);
  const auto bytes = OctetSpan(t.data);
  tile.data.assign(bytes.begin(), bytes.end());
  return tile;
}

}  // namespace fleetloc::transport
