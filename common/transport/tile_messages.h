// Tile streaming on the wire (TileRequest, Tile) as plain values, and the one place they are
// converted: the vehicle's tile client (tile_client.h) and the map server's tile service both call
// these. Checking a received request (wire_version, ids, sizes) stays with its receiver.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "mosaic/tile_key.h"
#include "transport/fleetloc_types.h"

namespace fleetloc::transport {

// One TileRequest as plain values.
struct TileAsk {
  std::string vehicle_id;
  uint32_t request_id = 0;
  std::string mosaic_id;  // empty: whatever the server serves
  std::vector<mosaic::TileKey> tiles;
};

// One Tile reply as plain values, as the server fills it; `data` is borrowed by the wire sample.
struct TileAnswer {
  std::string vehicle_id;
  uint32_t request_id = 0;
  mosaic::TileKey key;
  std::string mosaic_id;
  long long version = 0;
  fleetloc_TileStatus status = fleetloc_TILE_ERROR;
  std::string error;
  std::span<const std::uint8_t> data;  // the encoded tile when status is TILE_OK
};

// One Tile as the vehicle keeps it (the bytes copied out of the sample).
struct ReceivedTile {
  mosaic::TileKey key;
  uint32_t request_id = 0;
  fleetloc_TileStatus status = fleetloc_TILE_ERROR;
  long long version = 0;
  std::string mosaic_id;
  std::string error;
  std::vector<std::uint8_t> data;  // encoded tile when status is TILE_OK
};

// The wire's request, stamped with wire_version; its tile sequence borrows `*addresses` (filled
// here), which must outlive the sample.
fleetloc_TileRequest ToIdl(const TileAsk& ask, std::vector<fleetloc_TileAddress>* addresses);
TileAsk FromIdl(const fleetloc_TileRequest& request);
// The wire's reply, stamped with wire_version; its data borrows `answer.data`.
fleetloc_Tile ToIdl(const TileAnswer& answer);
ReceivedTile FromIdl(const fleetloc_Tile& tile);

}  // namespace fleetloc::transport
