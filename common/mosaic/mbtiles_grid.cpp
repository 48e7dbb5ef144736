// Web Mercator tile grid math of the MBTiles export (see mbtiles_grid.h).
#include "mosaic/mbtiles_grid.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace fleetloc::mosaic {
namespace {

constexpr double kEarthRadius = 6378137.0;  // EPSG:3857 sphere
constexpr double kPi = 3.14159265358979323846;
constexpr double kHalfWorld = kPi * kEarthRadius;
constexpr double kDeg = kPi / 180.0;

}  // namespace

Result<MercatorPlacement> PlaceAt(const MercatorAnchor& anchor) {
  if (!std::isfinite(anchor.lat_deg) || !std::isfinite(anchor.lon_deg) ||
      std::abs(anchor.lat_deg) > 85.0 || std::abs(anchor.lon_deg) > 180.0) {
    return InvalidInput("anchor " + std::to_string(anchor.lat_deg) + ", " +
                        std::to_string(anchor.lon_deg) +
                        " is outside Web Mercator's range (|lat| <= 85, |lon| <= 180 degrees)");
  }
  MercatorPlacement p;
  p.mx0 = kEarthRadius * anchor.lon_deg * kDeg;
  p.my0 = kEarthRadius * std::log(std::tan(kPi / 4.0 + anchor.lat_deg * kDeg / 2.0));
  p.scale = 1.0 / std::cos(anchor.lat_deg * kDeg);
  return p;
}

double MercXToLon(double mx) { return mx / kEarthRadius / kDeg; }
double MercYToLat(double my) {
  return (2.0 * std::atan(std::exp(my / kEarthRadius)) - kPi / 2.0) / kDeg;
}

double TileSpanMerc(int zoom) { return 2.0 * kHalfWorld / std::ldexp(1.0, zoom); }

int TmsRow(int zoom, int xyz_row) { return (1 << zoom) - 1 - xyz_row; }

MercBounds FloorBounds(const MosaicLayout& layout, const MercatorPlacement& placement) {
  const geometry::Geotransform& g = layout.geo;
  const double x0 = g.origin_x, x1 = g.origin_x + layout.width_px * g.resolution;
  const double y1 = g.origin_y, y0 = g.origin_y - layout.height_px * g.resolution;
  return {placement.MapToMercX(x0), placement.MapToMercY(y0), placement.MapToMercX(x1),
          placement.MapToMercY(y1)};
}

MercTileRange TilesCovering(const MercBounds& b, int zoom) {
  const double span = TileSpanMerc(zoom);
  const int last = (1 << zoom) - 1;
  // Lower edges floor, upper edges ceil - 1, so an edge exactly on a tile border stays out.
  auto index = [&](double v) { return std::clamp(static_cast<int>(std::floor(v)), 0, last); };
  auto index_end = [&](double v) {
    return std::clamp(static_cast<int>(std::ceil(v)) - 1, 0, last);
  };
  MercTileRange r;
  r.zoom = zoom;
  r.col0 = index((b.x0 + kHalfWorld) / span);
  r.col1 = std::max(r.col0, index_end((b.x1 + kHalfWorld) / span));
  r.xyz_row0 = index((kHalfWorld - b.y1) / span);
  r.xyz_row1 = std::max(r.xyz_row0, index_end((kHalfWorld - b.y0) / span));
  return r;
}

double MapMetresPerPixel(int zoom, const MercatorPlacement& placement) {
  return TileSpanMerc(zoom) / kMbtilesTileSize / placement.scale;
}

Result<ZoomRange> ChooseZooms(const MosaicLayout& layout, const MercatorPlacement& placement,
                              int zoom_cap) {
  const double res = layout.geo.resolution;
  if (!(res > 0.0) || layout.width_px <= 0 || layout.height_px <= 0) {
    return InvalidInput("the mosaic has no pixels or no resolution");
  }
  if (zoom_cap < 0 || zoom_cap > kMbtilesMaxZoom) {
    return InvalidInput("--max-zoom " + std::to_string(zoom_cap) + " is outside 0.." +
                        std::to_string(kMbtilesMaxZoom));
  }
  ZoomRange z;
  while (z.full_detail_zoom <= kMbtilesMaxZoom &&
         MapMetresPerPixel(z.full_detail_zoom, placement) > res * (1.0 + 1e-9)) {
    ++z.full_detail_zoom;
  }
  z.max_zoom = std::min(z.full_detail_zoom, zoom_cap);
  const double side = std::max(layout.width_px, layout.height_px) * res;
  while (z.min_zoom < z.max_zoom &&
         MapMetresPerPixel(z.min_zoom + 1, placement) * kMbtilesTileSize >= side) {
    ++z.min_zoom;
  }
  return z;
}

int SourceLevel(const MosaicLayout& layout, double metres_per_pixel) {
  int level = 0;
  while (level + 1 < layout.levels &&
         layout.geo.AtLevel(level + 1).resolution <= metres_per_pixel * (1.0 + 1e-9)) {
    ++level;
  }
  return level;
}

}  // namespace fleetloc::mosaic

namespace fleetloc::mosaic {

Result<MbtilesPlan> PlanMbtiles(const MosaicLayout& layout, const MercatorAnchor& anchor,
                                int zoom_cap) {
  Result<MercatorPlacement> placement = PlaceAt(anchor);
  if (!placement.ok()) return placement.status();
  Result<ZoomRange> zooms = ChooseZooms(layout, *placement, zoom_cap);
  if (!zooms.ok()) return zooms.status();
  MbtilesPlan plan;
  plan.placement = *placement;
  plan.bounds = FloorBounds(layout, *placement);
  plan.zooms = *zooms;
  for (int z = zooms->min_zoom; z <= zooms->max_zoom; ++z) {
    plan.ranges.push_back(TilesCovering(plan.bounds, z));
    plan.total_tiles += plan.ranges.back().Count();
  }
  return plan;
}

cv::Mat RenderTile(RasterSource& source, const MbtilesPlan& plan, int zoom, int col, int xyz_row) {
  const MosaicLayout& layout = source.layout();
  const MercatorPlacement& p = plan.placement;
  const double span = TileSpanMerc(zoom), half_world = span * std::ldexp(1.0, zoom) / 2.0;
  // The tile's top-left corner in map metres, and map metres per tile pixel.
  const double x_left = p.MercToMapX(col * span - half_world);
  const double y_top = p.MercToMapY(half_world - xyz_row * span);
  const double tile_res = MapMetresPerPixel(zoom, p);
  const int level = SourceLevel(layout, tile_res);
  const geometry::Geotransform g = layout.geo.AtLevel(level);
  const double s = tile_res / g.resolution;  // level pixels per tile pixel
  const double u0 = (x_left - g.origin_x) / g.resolution, v0 = (g.origin_y - y_top) / g.resolution;
  const double extent = kMbtilesTileSize * s;
  // The block of the level that covers the tile, one pixel of margin for the linear warp.
  const int bx0 = static_cast<int>(std::floor(u0)) - 1, by0 = static_cast<int>(std::floor(v0)) - 1;
  const int bx1 = static_cast<int>(std::ceil(u0 + extent)) + 1;
  const int by1 = static_cast<int>(std::ceil(v0 + extent)) + 1;
  cv::Mat block = source.ReadBlock(level, cv::Rect(bx0, by0, bx1 - bx0, by1 - by0));
  double sx = 1.0, sy = 1.0;
  if (s > 1.0) {  // shrink first so every source pixel counts (INTER_AREA), then place exactly
    const cv::Size small(std::max(1, static_cast<int>(std::lround(block.cols / s))),
                         std::max(1, static_cast<int>(std::lround(block.rows / s))));
    cv::resize(block, block, small, 0, 0, cv::INTER_AREA);
    sx = static_cast<double>(small.width) / (bx1 - bx0);
    sy = static_cast<double>(small.height) / (by1 - by0);
  }
  // Tile pixel i's centre is level coordinate u0 + (i + 0.5) s; in the (shrunk) block's pixel
  // index coordinates that is (u0 + (i + 0.5) s - bx0) sx - 0.5.
  const cv::Matx23d m(s * sx, 0.0, (u0 - bx0 + 0.5 * s) * sx - 0.5, 0.0, s * sy,
                      (v0 - by0 + 0.5 * s) * sy - 0.5);
  cv::Mat tile;
  cv::warpAffine(block, tile, m, cv::Size(kMbtilesTileSize, kMbtilesTileSize),
                 cv::INTER_LINEAR | cv::WARP_INVERSE_MAP, cv::BORDER_CONSTANT, cv::Scalar(0));
  return tile;
}

}  // namespace fleetloc::mosaic
