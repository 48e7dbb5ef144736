// Import of an image file into a new tiled, versioned mosaic (`fleetctl mosaic import`).
#pragma once

#include <functional>
#include <optional>
#include <string>

#include "base/status.h"
#include "mosaic/raster_source.h"
#include "mosaic/row_image_io.h"

namespace fleetloc::mosaic {

struct ImportOptions {
  double resolution_m = 0.0;  // metres per level-0 pixel, > 0
  // Map position of the image's top-left corner; default (0, height_px * resolution_m), so the
  // mosaic covers x >= 0, y >= 0 of the map.
  std::optional<double> origin_x_m;
  std::optional<double> origin_y_m;
  int tile_size_px = 256;
};

// Called now and then with level-0 rows done so far and the total (rows_done == total at the end).
using ImportProgress = std::function<void(int rows_done, int rows_total)>;

// Cuts `image_path` into tiles of every pyramid level and writes them as version 1 of a new mosaic
// at `out_db`. The image is read in strips (PNG and binary PGM/PPM are streamed; other formats are
// decoded whole by OpenCV) and converted to 8-bit gray; peak memory is about
// 2 × width × tile_size bytes plus the decoder's. The mosaic is built in `out_db`.partial and moved
// into place only when complete. Returns the stored layout. NotFound / InvalidInput naming the file
// for a missing or undecodable image, bad options or an existing `out_db`; Internal on I/O errors.
Result<MosaicLayout> ImportImage(const std::string& image_path, const ImportOptions& options,
                                 const std::string& out_db, const ImportProgress& progress = {});

// The same import from rows produced by the caller (e.g. a mosaic blended from a mapping run):
// every row of `reader`, top to bottom, becomes version 1 of a new mosaic at `out_db`, written
// through `out_db`.partial. Peak memory beyond the reader's is about 2 × width × tile_size bytes.
// InvalidInput for bad options or an existing `out_db`; the reader's error; Internal on I/O errors.
Result<MosaicLayout> ImportRows(GrayRowReader& reader, const ImportOptions& options,
                                const std::string& out_db, const ImportProgress& progress = {});

// InvalidInput when a new mosaic cannot be created at `out_db` (it exists, or its directory does
// not): lets a long job fail before it starts.
Status CheckNewMosaicPath(const std::string& out_db);

}  // namespace fleetloc::mosaic
