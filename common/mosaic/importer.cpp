// Image import: streamed rows → pyramid builder → tile store, in one version transaction.
#include "mosaic/importer.h"

#include <cmath>
#include <filesystem>
#include <vector>

#include "mosaic/pyramid_builder.h"
#include "mosaic/row_image_io.h"
#include "mosaic/tile_key.h"
#include "mosaic/tile_store.h"
#include "sqlite/sqlite_util.h"

namespace fleetloc::mosaic {
namespace {

namespace fs = std::filesystem;

// True if a database's write-ahead log still holds frames (then the main file alone is incomplete).
bool HasUnfoldedWal(const std::string& path) {
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(path + "-wal", ec);
  return !ec && size > 0;
}

Status ValidateOptions(const ImportOptions& options) {
  if (!(options.resolution_m > 0.0) || !std::isfinite(options.resolution_m)) {
    return InvalidInput("--resolution must be a positive number of metres per pixel");
  }
  const auto finite = [](const std::optional<double>& v) { return !v || std::isfinite(*v); };
  if (!finite(options.origin_x_m) || !finite(options.origin_y_m)) {
    return InvalidInput("--origin must be finite");
  }
  const int t = options.tile_size_px;
  if (t < 16 || t > 4096 || (t & (t - 1)) != 0) {
    return InvalidInput("tile size must be a power of two in [16, 4096]");
  }
  return Status::Ok();
}

MosaicLayout LayoutFor(const GrayRowReader& reader, const ImportOptions& options) {
  MosaicLayout layout;
  layout.width_px = reader.width();
  layout.height_px = reader.height();
  layout.tile_size_px = options.tile_size_px;
  layout.levels = PyramidLevelCount(layout.width_px, layout.height_px, options.tile_size_px);
  layout.geo.resolution = options.resolution_m;
  layout.geo.origin_x = options.origin_x_m.value_or(0.0);
  layout.geo.origin_y = options.origin_y_m.value_or(layout.height_px * options.resolution_m);
  return layout;
}

// Streams all rows of the image through the pyramid builder into the open version of `store`.
Status WriteAllTiles(GrayRowReader& reader, TileStore& store, const ImportProgress& progress) {
  PyramidBuilder builder(store.layout(), [&store](const TileKey& key, const cv::Mat& tile) {
    return store.PutTile(key, tile);
  });
  std::vector<std::uint8_t> row(reader.width());
  const int total = reader.height();
  const int report_every = std::max(1, total / 100);
  for (int y = 0; y < total; ++y) {
    FLEETLOC_RETURN_IF_ERROR(reader.ReadRow(row));
    FLEETLOC_RETURN_IF_ERROR(builder.AddRow(row));
    if (progress && ((y + 1) % report_every == 0 || y + 1 == total)) progress(y + 1, total);
  }
  return builder.Finish();
}

Result<MosaicLayout> BuildMosaic(GrayRowReader& reader, const ImportOptions& options,
                                 const std::string& db_path, const ImportProgress& progress) {
  Result<std::unique_ptr<TileStore>> store = TileStore::Create(db_path, LayoutFor(reader, options));
  if (!store.ok()) return store.status();
  FLEETLOC_RETURN_IF_ERROR((*store)->BeginVersion());
  FLEETLOC_RETURN_IF_ERROR(WriteAllTiles(reader, **store, progress));
  Result<long long> version = (*store)->CommitVersion();
  if (!version.ok()) return version.status();
  return (*store)->layout();  // the store closes here, folding its WAL into the file
}

}  // namespace

Status CheckNewMosaicPath(const std::string& out_db) {
  std::error_code ec;
  if (fs::exists(out_db, ec)) {
    return InvalidInput(out_db + ": already exists (remove it or choose another --out)");
  }
  if (!fs::is_directory(fs::absolute(out_db, ec).parent_path(), ec)) {
    return InvalidInput(out_db + ": the directory does not exist");
  }
  return Status::Ok();
}

Result<MosaicLayout> ImportImage(const std::string& image_path, const ImportOptions& options,
                                 const std::string& out_db, const ImportProgress& progress) {
  FLEETLOC_RETURN_IF_ERROR(ValidateOptions(options));
  FLEETLOC_RETURN_IF_ERROR(CheckNewMosaicPath(out_db));
  Result<std::unique_ptr<GrayRowReader>> reader = OpenGrayRowReader(image_path);
  if (!reader.ok()) return reader.status();
  return ImportRows(**reader, options, out_db, progress);
}

Result<MosaicLayout> ImportRows(GrayRowReader& reader, const ImportOptions& options,
                                const std::string& out_db, const ImportProgress& progress) {
  FLEETLOC_RETURN_IF_ERROR(ValidateOptions(options));
  FLEETLOC_RETURN_IF_ERROR(CheckNewMosaicPath(out_db));
  const std::string partial = out_db + ".partial";
  sqlite::RemoveDatabaseFiles(partial);  // left over from an interrupted import
  Result<MosaicLayout> layout = BuildMosaic(reader, options, partial, progress);
  std::error_code ec;
  if (layout.ok() && HasUnfoldedWal(partial)) {
    layout = Internal(partial + ": the write-ahead log was not folded into the mosaic");
  }
  if (layout.ok()) {
    fs::rename(partial, out_db, ec);
    if (ec)
      layout = Internal(out_db + ": cannot move the finished mosaic into place: " + ec.message());
  }
  if (!layout.ok()) sqlite::RemoveDatabaseFiles(partial);
  return layout;
}

}  // namespace fleetloc::mosaic
