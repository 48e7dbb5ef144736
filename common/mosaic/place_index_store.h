// The place-index cache in a mosaic file: a serialized place index (an opaque blob here; its
// format belongs to relocalization::PlaceIndex) kept in the table `place_index(mosaic_version, key,
// data)`, so the map server and `fleetctl reloc` build it once per mosaic version and index
// options (`key`) and then load it. Adapter: SQLite only, no algorithm.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "base/status.h"

namespace fleetloc::mosaic {

// The blob stored for (mosaic_version, key), or nullopt when there is none (or no table yet).
// NotFound for a missing file; Internal on SQLite errors.
Result<std::optional<std::vector<std::uint8_t>>> ReadPlaceIndexBlob(const std::string& mosaic_path,
                                                                    long long mosaic_version,
                                                                    const std::string& key);

// Stores the blob for (mosaic_version, key) in one transaction, replacing blobs of older mosaic
// versions with the same key (they can never be used again). NotFound for a missing file;
// Internal on SQLite errors (e.g. a read-only file).
Status WritePlaceIndexBlob(const std::string& mosaic_path, long long mosaic_version,
                           const std::string& key, std::span<const std::uint8_t> blob);

}  // namespace fleetloc::mosaic
