// The Web Mercator tile grid of an MBTiles export (spec 1.3, EPSG:3857, 256-pixel tiles, TMS rows:
// row 0 at the bottom). Pure math: a floor in map metres is placed at an anchor (lat, lon) — map
// origin (0, 0) at the anchor, one map metre = 1/cos(lat) Web Mercator metres so lengths stay
// true near the anchor — and from that the zoom range, tile ranges and tile footprints follow.
#pragma once

#include <string>
#include <vector>

#include "base/status.h"
#include "mosaic/raster_source.h"

namespace fleetloc::mosaic {

inline constexpr int kMbtilesTileSize = 256;
inline constexpr int kMbtilesMaxZoom = 30;  // tile indices stay below 2^30 (int)
inline constexpr int kGdalMaxZoom = 22;     // GDAL's MBTiles driver (so QGIS) opens no finer zoom

// Where the floor's map frame sits on the globe.
struct MercatorAnchor {
  double lat_deg = 0.0;  // |lat| <= 85 (Web Mercator's useful range)
  double lon_deg = 0.0;  // -180 .. 180
};

// Map frame (metres, y up) ↔ Web Mercator metres (EPSG:3857) for an anchor.
struct MercatorPlacement {
  double mx0 = 0.0, my0 = 0.0;  // Web Mercator metres of the map origin
  double scale = 1.0;           // Web Mercator metres per map metre = 1 / cos(lat)
  double MapToMercX(double x) const { return mx0 + x * scale; }
  double MapToMercY(double y) const { return my0 + y * scale; }
  double MercToMapX(double mx) const { return (mx - mx0) / scale; }
  double MercToMapY(double my) const { return (my - my0) / scale; }
};

// InvalidInput for a non-finite anchor, |lat| > 85 or |lon| > 180.
Result<MercatorPlacement> PlaceAt(const MercatorAnchor& anchor);

// Web Mercator metres ↔ WGS84 degrees.
double MercXToLon(double mx);
double MercYToLat(double my);

// Web Mercator metres per tile at `zoom` (2πR / 2^zoom).
double TileSpanMerc(int zoom);

// An inclusive range of tiles of one zoom; rows in XYZ order (row 0 at the top) and TMS order.
struct MercTileRange {
  int zoom = 0;
  int col0 = 0, col1 = -1;
  int xyz_row0 = 0, xyz_row1 = -1;  // top .. bottom
  long long Count() const {
    return col1 < col0 || xyz_row1 < xyz_row0
               ? 0
               : static_cast<long long>(col1 - col0 + 1) * (xyz_row1 - xyz_row0 + 1);
  }
};
// TMS row (0 at the bottom) of an XYZ row (0 at the top) at `zoom`.
int TmsRow(int zoom, int xyz_row);

// Axis-aligned bounds in Web Mercator metres.
struct MercBounds {
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // west, south, east, north
};

// The floor's bounds: the whole level-0 raster of `layout` placed by `placement`.
MercBounds FloorBounds(const MosaicLayout& layout, const MercatorPlacement& placement);

// The tiles of `zoom` that `bounds` touches (a bound exactly on a tile edge does not take the
// next tile).
MercTileRange TilesCovering(const MercBounds& bounds, int zoom);

// The zoom range: full_detail_zoom is the coarsest zoom whose ground resolution (true metres per
// pixel, i.e. map metres) is at least as fine as the mosaic's level 0, so no detail is lost;
// maxzoom that zoom or `zoom_cap` if lower (detail is then lost); minzoom the finest zoom at which
// the whole floor's longer side fits one tile width (so at most 2 × 2 tiles), never above maxzoom.
// InvalidInput for a zoom_cap outside 0..kMbtilesMaxZoom.
struct ZoomRange {
  int min_zoom = 0, max_zoom = 0;
  int full_detail_zoom = 0;  // may exceed max_zoom (then up to kMbtilesMaxZoom + 1)
};
Result<ZoomRange> ChooseZooms(const MosaicLayout& layout, const MercatorPlacement& placement,
                              int zoom_cap);

// Map metres per tile pixel at `zoom` for `placement`.
double MapMetresPerPixel(int zoom, const MercatorPlacement& placement);

// The pyramid level to resample a zoom from: the coarsest level whose resolution is still at
// least as fine as `metres_per_pixel` (level 0 when none is).
int SourceLevel(const MosaicLayout& layout, double metres_per_pixel);

}  // namespace fleetloc::mosaic

namespace fleetloc::mosaic {

// Every zoom's tile range for the floor, coarsest first, and their total.
struct MbtilesPlan {
  MercatorPlacement placement;
  MercBounds bounds;
  ZoomRange zooms;
  std::vector<MercTileRange> ranges;  // min_zoom .. max_zoom
  long long total_tiles = 0;
};
Result<MbtilesPlan> PlanMbtiles(const MosaicLayout& layout, const MercatorAnchor& anchor,
                                int zoom_cap);

// Renders tile (zoom, col, xyz_row) of `plan` from `source` as a 256 × 256 CV_8UC1 image: read
// from the pyramid level SourceLevel picks, shrunk with INTER_AREA to about the tile's pixel size,
// then placed to the sub-pixel with a linear warp. Pixels outside the floor are 0 (black).
cv::Mat RenderTile(RasterSource& source, const MbtilesPlan& plan, int zoom, int col, int xyz_row);

}  // namespace fleetloc::mosaic
