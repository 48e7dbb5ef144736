// Writes a mosaic as an MBTiles 1.3 file (`fleetctl mosaic export-mbtiles`): 256 × 256 gray PNG
// tiles in Web Mercator, TMS rows, the spec's metadata. Written to "<out>.tmp" and renamed at the
// end, so the output is either complete or absent.
#pragma once

#include <functional>
#include <string>

#include "base/status.h"
#include "mosaic/mbtiles_grid.h"
#include "mosaic/raster_source.h"

namespace fleetloc::mosaic {

struct MbtilesOptions {
  MercatorAnchor anchor;
  long long max_tiles = 100000;  // refuse (InvalidInput) a larger export
  int max_zoom = kGdalMaxZoom;   // no finer zoom (GDAL / QGIS open up to 22)
  std::string name;              // metadata name (default: the mosaic id)
};

// The metadata rows: name, format=png, bounds (west,south,east,north degrees), center
// (lon,lat,minzoom), minzoom, maxzoom, type=baselayer, version (the mosaic version),
// description (mosaic id, version, resolution, anchor).
std::vector<std::pair<std::string, std::string>> MbtilesMetadata(const MosaicLayout& layout,
                                                                 const MbtilesPlan& plan,
                                                                 const MbtilesOptions& options);

// Plans, checks the tile count against options.max_tiles and writes every tile of the plan.
// `progress(done, total)` after each tile. InvalidInput for a bad anchor or too many tiles;
// Internal for an SQLite or encoding failure (the temporary file is removed).
Result<MbtilesPlan> ExportMbtiles(RasterSource& source, const MbtilesOptions& options,
                                  const std::string& out_path,
                                  const std::function<void(long long, long long)>& progress);

}  // namespace fleetloc::mosaic
