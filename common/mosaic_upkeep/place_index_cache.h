// A mosaic file's place index (global relocalization): loaded from the file's place_index table
// when one is cached for the mosaic's version and the index options, else built from the mosaic's
// pixels (with progress) and cached there. Shared by the map server, which serves the index to its
// vehicles, and by `fleetctl reloc` / `fleetctl bench reloc`.
#pragma once

#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

#include "base/status.h"
#include "mosaic/raster_source.h"
#include "relocalization/place_index.h"

namespace fleetloc::mosaic_upkeep {

struct LoadedPlaceIndex {
  relocalization::PlaceIndex index;
  std::vector<std::uint8_t> blob;  // index.Serialize(), as cached
  bool from_cache = false;
  double seconds = 0.0;  // to load (deserialize + LSH tables) or to build
};

// The cache key of an index built with `options` (detector, grid and LSH settings).
std::string PlaceIndexKey(const relocalization::PlaceIndexOptions& options);

enum class IndexCache {
  kUse,      // load the cached blob if there is a usable one, else build and store it
  kRebuild,  // build and store, ignoring a cached blob
  kIgnore,   // build, neither read nor write the cache
};

// The index of the mosaic at `mosaic_path` (whose pixels `view` reads, at the store's version),
// as `cache` says: a cached blob for (version, key) that cannot be used is logged and rebuilt; a
// failure to store is logged, not fatal. The build's error otherwise (e.g. a textureless floor,
// or "cancelled" once *cancel is set).
Result<LoadedPlaceIndex> LoadOrBuildPlaceIndex(const std::string& mosaic_path,
                                               mosaic::RasterSource& view,
                                               const relocalization::PlaceIndexOptions& options,
                                               IndexCache cache,
                                               const std::atomic<bool>* cancel = nullptr);

}  // namespace fleetloc::mosaic_upkeep
