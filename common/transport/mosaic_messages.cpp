// MosaicInfo / TileAddress conversions.
#include "transport/mosaic_messages.h"

#include <cmath>

#include "transport/wire_util.h"

namespace fleetloc::transport {

fleetloc_MosaicInfo ToIdl(const mosaic::MosaicLayout& layout, const std::string& server_id,
                          const mosaic::TileOwnership& owned) {
  fleetloc_MosaicInfo info{};
  info.wire_version = fleetloc_CURRENT_WIRE_VERSION;
  SetBounded(info.server_id, server_id);
  SetBounded(info.mosaic_id, layout.mosaic_id);
  info.version = layout.version;
  info.width_px = layout.width_px;
  info.height_px = layout.height_px;
  info.tile_size_px = layout.tile_size_px;
  info.levels = static_cast<uint16_t>(layout.levels);
  info.origin_x = layout.geo.origin_x;
  info.origin_y = layout.geo.origin_y;
  info.resolution = layout.geo.resolution;
  SetBounded(info.tile_encoding, "png");
  info.owned_col_begin = owned.col_begin;
  info.owned_col_end = owned.col_end;
  info.owned_row_begin = owned.row_begin;
  info.owned_row_end = owned.row_end;
  info.stamp = NowStamp();
  return info;
}

Result<mosaic::MosaicLayout> LayoutFromIdl(const fleetloc_MosaicInfo& info) {
  const std::string where = "MosaicInfo from '" + GetBounded(info.server_id) + "': ";
  if (info.wire_version != fleetloc_CURRENT_WIRE_VERSION) {
    return InvalidInput(where + "wire_version " + std::to_string(info.wire_version) + " is not " +
                        std::to_string(fleetloc_CURRENT_WIRE_VERSION));
  }
  if (info.width_px <= 0 || info.height_px <= 0) return InvalidInput(where + "size not positive");
  if (info.tile_size_px <= 0 || info.tile_size_px % 2 != 0) {
    return InvalidInput(where + "tile_size_px must be positive and even");
  }
  if (info.levels != mosaic::PyramidLevelCount(info.width_px, info.height_px, info.tile_size_px)) {
    return InvalidInput(where + "levels do not match the size");
  }
  if (!std::isfinite(info.origin_x) || !std::isfinite(info.origin_y) || !(info.resolution > 0) ||
      !std::isfinite(info.resolution)) {
    return InvalidInput(where + "geotransform not finite and positive");
  }
  mosaic::MosaicLayout layout;
  layout.mosaic_id = GetBounded(info.mosaic_id);
  layout.width_px = info.width_px;
  layout.height_px = info.height_px;
  layout.tile_size_px = info.tile_size_px;
  layout.levels = info.levels;
  layout.geo.origin_x = info.origin_x;
  layout.geo.origin_y = info.origin_y;
  layout.geo.resolution = info.resolution;
  layout.version = info.version;
  return layout;
}

mosaic::TileOwnership OwnershipFromIdl(const fleetloc_MosaicInfo& info) {
  return {info.owned_col_begin, info.owned_col_end, info.owned_row_begin, info.owned_row_end};
}

fleetloc_TileAddress ToIdl(const mosaic::TileKey& key) {
  return {static_cast<uint16_t>(key.level), key.col, key.row};
}

mosaic::TileKey FromIdl(const fleetloc_TileAddress& address) {
  return {address.level, address.col, address.row};
}

bool InGrid(const mosaic::MosaicLayout& layout, const mosaic::TileKey& key) {
  return key.level >= 0 && key.level < layout.levels && key.col >= 0 && key.row >= 0 &&
         key.col < mosaic::TileColumns(layout, key.level) &&
         key.row < mosaic::TileRows(layout, key.level);
}

}  // namespace fleetloc::transport
