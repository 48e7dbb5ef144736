// MBTiles 1.3 writer over SQLite (see mbtiles_writer.h).
#include "mosaic/mbtiles_writer.h"

#include <sqlite3.h>

#include <filesystem>
#include <iomanip>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "sqlite/sqlite_util.h"

namespace fleetloc::mosaic {
namespace {

std::string Degrees(double v) {
  std::ostringstream s;
  s << std::setprecision(12) << v;
  return s.str();
}

Status WriteMetadata(sqlite3* db, const std::vector<std::pair<std::string, std::string>>& rows) {
  Result<sqlite::Stmt> insert =
      sqlite::Prepare(db, "INSERT INTO metadata(name, value) VALUES(?, ?)");
  if (!insert.ok()) return insert.status();
  for (const auto& [name, value] : rows) {
    sqlite::ScopedReset reset(insert->get());
    sqlite3_bind_text(insert->get(), 1, name.c_str(), -1, SQLITE_TRANSIENT);
    sqlite3_bind_text(insert->get(), 2, value.c_str(), -1, SQLITE_TRANSIENT);
    if (sqlite3_step(insert->get()) != SQLITE_DONE) return Internal(sqlite::ErrorMessage(db));
  }
  return Status::Ok();
}

Status WriteTiles(sqlite3* db, RasterSource& source, const MbtilesPlan& plan,
                  const std::function<void(long long, long long)>& progress) {
  Result<sqlite::Stmt> insert = sqlite::Prepare(
      db, "INSERT INTO tiles(zoom_level, tile_column, tile_row, tile_data) VALUES(?, ?, ?, ?)");
  if (!insert.ok()) return insert.status();
  long long done = 0;
  for (const MercTileRange& r : plan.ranges) {
    for (int row = r.xyz_row0; row <= r.xyz_row1; ++row) {
      for (int col = r.col0; col <= r.col1; ++col) {
        std::vector<unsigned char> png;
        if (!cv::imencode(".png", RenderTile(source, plan, r.zoom, col, row), png)) {
          return Internal("cannot encode tile as PNG");
        }
        sqlite::ScopedReset reset(insert->get());
        sqlite3_bind_int(insert->get(), 1, r.zoom);
        sqlite3_bind_int(insert->get(), 2, col);
        sqlite3_bind_int(insert->get(), 3, TmsRow(r.zoom, row));
        sqlite3_bind_blob(insert->get(), 4, png.data(), static_cast<int>(png.size()),
                          SQLITE_TRANSIENT);
        if (sqlite3_step(insert->get()) != SQLITE_DONE) return Internal(sqlite::ErrorMessage(db));
        if (progress) progress(++done, plan.total_tiles);
      }
    }
  }
  return Status::Ok();
}

Status WriteFile(RasterSource& source, const MbtilesPlan& plan, const MbtilesOptions& options,
                 const std::string& path,
                 const std::function<void(long long, long long)>& progress) {
  Result<sqlite::Db> db = sqlite::OpenDb(path, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE);
  if (!db.ok()) return db.status();
  FLEETLOC_RETURN_IF_ERROR(sqlite::Exec(db->get(),
                                        "CREATE TABLE metadata (name TEXT, value TEXT);"
                                        "CREATE TABLE tiles (zoom_level INTEGER, tile_column "
                                        "INTEGER, tile_row INTEGER, tile_data BLOB);"
                                        "BEGIN;"));
  FLEETLOC_RETURN_IF_ERROR(
      WriteMetadata(db->get(), MbtilesMetadata(source.layout(), plan, options)));
  FLEETLOC_RETURN_IF_ERROR(WriteTiles(db->get(), source, plan, progress));
  return sqlite::Exec(db->get(),
                      "COMMIT;"
                      "CREATE UNIQUE INDEX tile_index ON tiles (zoom_level, tile_column, tile_row);"
                      "CREATE UNIQUE INDEX name ON metadata (name);");
}

}  // namespace

std::vector<std::pair<std::string, std::string>> MbtilesMetadata(const MosaicLayout& layout,
                                                                 const MbtilesPlan& plan,
                                                                 const MbtilesOptions& options) {
  const MercBounds& b = plan.bounds;
  const double west = MercXToLon(b.x0), east = MercXToLon(b.x1);
  const double south = MercYToLat(b.y0), north = MercYToLat(b.y1);
  const double lon_c = MercXToLon((b.x0 + b.x1) / 2), lat_c = MercYToLat((b.y0 + b.y1) / 2);
  const std::string id_version = layout.mosaic_id + " version " + std::to_string(layout.version);
  std::ostringstream description;
  description << "fleetloc floor mosaic " << id_version << ", " << layout.geo.resolution
              << " m/px, map origin at lat " << Degrees(options.anchor.lat_deg) << " lon "
              << Degrees(options.anchor.lon_deg) << " (local metres, not surveyed)";
  return {
      {"name", options.name.empty() ? layout.mosaic_id : options.name},
      {"format", "png"},
      {"bounds", Degrees(west) + "," + Degrees(south) + "," + Degrees(east) + "," + Degrees(north)},
      {"center", Degrees(lon_c) + "," + Degrees(lat_c) + "," + std::to_string(plan.zooms.min_zoom)},
      {"minzoom", std::to_string(plan.zooms.min_zoom)},
      {"maxzoom", std::to_string(plan.zooms.max_zoom)},
      {"type", "baselayer"},
      {"version", std::to_string(layout.version)},
      {"description", description.str()}};
}

Result<MbtilesPlan> ExportMbtiles(RasterSource& source, const MbtilesOptions& options,
                                  const std::string& out_path,
                                  const std::function<void(long long, long long)>& progress) {
  Result<MbtilesPlan> plan = PlanMbtiles(source.layout(), options.anchor, options.max_zoom);
  if (!plan.ok()) return plan.status();
  if (plan->total_tiles > options.max_tiles) {
    return InvalidInput("the export would write " + std::to_string(plan->total_tiles) +
                        " tiles (zooms " + std::to_string(plan->zooms.min_zoom) + ".." +
                        std::to_string(plan->zooms.max_zoom) + "), more than --max-tiles " +
                        std::to_string(options.max_tiles));
  }
  const std::string tmp = out_path + ".tmp";
  sqlite::RemoveDatabaseFiles(tmp);
  Status written = WriteFile(source, *plan, options, tmp, progress);
  std::error_code ec;
  if (written.ok()) {
    std::filesystem::rename(tmp, out_path, ec);
    if (ec) written = Internal("cannot rename " + tmp + " to " + out_path + ": " + ec.message());
  }
  if (!written.ok()) {
    sqlite::RemoveDatabaseFiles(tmp);
    return written;
  }
  return plan;
}

}  // namespace fleetloc::mosaic
