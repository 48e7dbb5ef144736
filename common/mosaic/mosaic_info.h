// A JSON description of a stored mosaic (`fleetctl mosaic info`): its metadata, typed, plus tile
// counts per level.
#pragma once

#include <nlohmann/json.hpp>

#include "base/status.h"
#include "mosaic/tile_store.h"

namespace fleetloc::mosaic {

// {"file", "format", "mosaic_id", "width", "height", "tile_size", "levels", "resolution",
//  "origin_x", "origin_y", "version", "created", "tiles_per_level": [...], "tiles": N} — numbers
// as JSON numbers; further metadata keys are copied as strings. Internal on SQLite failure.
Result<nlohmann::json> DescribeMosaic(TileStore& store);

}  // namespace fleetloc::mosaic
