// The place index of a mosaic file for `fleetctl reloc` and `fleetctl bench reloc`: loaded from
// the mosaic's place_index table when cached for its version and options, else built (progress on
// stderr) and cached there; and a relocalization result as JSON.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "base/status.h"
#include "mapmatch/place_index.h"
#include "mapmatch/relocalizer.h"
#include "mosaic/raster_source.h"

namespace fleetloc::fleetctl {

struct LoadedPlaceIndex {
  mapmatch::PlaceIndex index;
  bool from_cache = false;
  double seconds = 0.0;  // to load (deserialize + LSH tables) or to build
  std::size_t blob_bytes = 0;
};

// The cache key of an index built with `options` (detector, grid and LSH settings).
std::string PlaceIndexKey(const mapmatch::PlaceIndexOptions& options);

enum class IndexCache {
  kUse,      // load the cached blob if there is a usable one, else build and store it
  kRebuild,  // build and store, ignoring a cached blob
  kIgnore,   // build, neither read nor write the cache
};

// The index of the mosaic at `mosaic_path` (whose pixels `view` reads, at the store's version),
// as `cache` says: a cached blob for (version, key) that cannot be used is logged and rebuilt; a
// failure to store is logged, not fatal. The build's error otherwise (e.g. a textureless floor).
Result<LoadedPlaceIndex> LoadOrBuildPlaceIndex(const std::string& mosaic_path,
                                               mosaic::RasterSource& view,
                                               const mapmatch::PlaceIndexOptions& options,
                                               IndexCache cache);

// found, pose, covariance (upper triangle as in poses.csv), reason, counts and stage times.
nlohmann::json RelocalizationJson(const mapmatch::Relocalization& result);

}  // namespace fleetloc::fleetctl
