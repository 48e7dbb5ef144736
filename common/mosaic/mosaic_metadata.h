// The metadata of a stored mosaic (the `metadata` table of the tile store): conversion between the
// key/value strings and MosaicLayout, with validation that names the offending key.
#pragma once

#include <map>
#include <string>

#include "base/status.h"
#include "mosaic/raster_source.h"

namespace fleetloc::mosaic {

inline constexpr char kMosaicFormat[] = "fleetloc-mosaic/1";

using Metadata = std::map<std::string, std::string>;

// Checks a layout before it is stored: id of 32 hex digits, sizes in [1, 2^24], tile size a power
// of two in [16, 4096], levels matching the sizes, finite origin, resolution > 0, version >= 0.
// InvalidInput naming the field otherwise.
Status ValidateLayout(const MosaicLayout& layout);

// All keys of the metadata table for a layout: format, mosaic_id, width, height, tile_size, levels,
// resolution, origin_x, origin_y, version, created (doubles printed to round-trip exactly).
Metadata LayoutToMetadata(const MosaicLayout& layout, const std::string& created_iso);

// Parses and validates metadata. InvalidInput naming the key that is missing or wrong (wrong
// format string, not a number, out of range, inconsistent levels).
Result<MosaicLayout> LayoutFromMetadata(const Metadata& metadata);

// A fresh random 128-bit mosaic id as 32 lowercase hex digits.
std::string NewMosaicId();

// The current UTC time as ISO 8601, e.g. "2024-05-01T12:00:00Z".
std::string IsoTimeNowUtc();

}  // namespace fleetloc::mosaic
