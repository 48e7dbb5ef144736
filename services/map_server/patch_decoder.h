// Checks a received PatchObservation and turns it into a patch record for the store: wire
// version, vehicle id, mosaic, resolution, finite pose, a covariance that is symmetric positive
// definite (a zero or negative one is malformed), quality, encoded size, and the PNG itself
// (header checked before decoding, so a forged size cannot exhaust memory).
#pragma once

#include <string>

#include "base/status.h"
#include "mosaic/patch_store.h"
#include "mosaic/raster_source.h"
#include "transport/fleetloc_types.h"

namespace fleetloc::map_server {

struct PatchLimits {
  int max_bytes = 4 << 20;
  int max_side_px = 4096;
};

struct DecodedPatch {
  Result<mosaic::PatchRecord> record = InvalidInput("not decoded");
  std::string reject_counter;  // when !record.ok(): the ServerCounters name of the reason
};

// Every check that needs no decoding (fields, sizes, the PNG's header). The record has neither
// image nor PNG bytes yet (transport::CopyPng copies them, once the patch is to be kept). `layout`:
// the mosaic served (its id and level-0 resolution must match the patch's).
DecodedPatch CheckPatch(const fleetloc_PatchObservation& sample, const mosaic::MosaicLayout& layout,
                        const PatchLimits& limits);

// Decodes a checked record's PNG into its image (so a corrupt image is refused before it is
// stored). InvalidInput naming the patch when it does not decode.
Status DecodePatchImage(mosaic::PatchRecord* record, const PatchLimits& limits);

// CheckPatch, then DecodePatchImage.
DecodedPatch DecodePatch(const fleetloc_PatchObservation& sample,
                         const mosaic::MosaicLayout& layout, const PatchLimits& limits);

}  // namespace fleetloc::map_server
