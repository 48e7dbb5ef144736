// Conversions between the mosaic's types (layout, tile keys, ownership) and the wire types
// MosaicInfo, TileAddress and TileUpdate. The only place that maps one to the other.
#pragma once

#include <string>
#include <vector>

#include "base/status.h"
#include "mosaic/raster_source.h"
#include "mosaic/tile_key.h"
#include "mosaic/tile_ownership.h"
#include "transport/fleetloc_types.h"

namespace fleetloc::transport {

fleetloc_MosaicInfo ToIdl(const mosaic::MosaicLayout& layout, const std::string& server_id,
                          const mosaic::TileOwnership& owned);
// The layout announced in `info`; InvalidInput naming the field if it is not a usable mosaic
// (unknown wire version, non-positive sizes, levels out of range, non-finite geotransform).
Result<mosaic::MosaicLayout> LayoutFromIdl(const fleetloc_MosaicInfo& info);
mosaic::TileOwnership OwnershipFromIdl(const fleetloc_MosaicInfo& info);

fleetloc_TileAddress ToIdl(const mosaic::TileKey& key);
mosaic::TileKey FromIdl(const fleetloc_TileAddress& address);

// Whether `key` names an existing tile of `layout` (level in range, column and row in its grid).
bool InGrid(const mosaic::MosaicLayout& layout, const mosaic::TileKey& key);

}  // namespace fleetloc::transport
