// Mosaic description as JSON.
#include "mosaic/mosaic_info.h"

#include <numeric>

namespace fleetloc::mosaic {

Result<nlohmann::json> DescribeMosaic(TileStore& store) {
  Result<Metadata> metadata = store.ReadMetadata();
  if (!metadata.ok()) return Internal(store.path() + ": " + metadata.status().message());
  Result<std::vector<long long>> counts = store.TileCountsPerLevel();
  if (!counts.ok()) return counts.status();
  const MosaicLayout layout = store.layout();
  nlohmann::json info = nlohmann::json::object();
  info["file"] = store.path();
  for (const auto& [name, value] : *metadata) info[name] = value;  // unknown keys stay strings
  info["format"] = kMosaicFormat;
  info["mosaic_id"] = layout.mosaic_id;
  info["width"] = layout.width_px;
  info["height"] = layout.height_px;
  info["tile_size"] = layout.tile_size_px;
  info["levels"] = layout.levels;
  info["resolution"] = layout.geo.resolution;
  info["origin_x"] = layout.geo.origin_x;
  info["origin_y"] = layout.geo.origin_y;
  info["version"] = layout.version;
  info["tiles_per_level"] = *counts;
  info["tiles"] = std::accumulate(counts->begin(), counts->end(), 0LL);
  return info;
}

}  // namespace fleetloc::mosaic
