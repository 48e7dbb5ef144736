// Fuzz target: a place-index blob as a vehicle receives it from the map server (and as cached in
// the mosaic file) — PlaceIndex::Deserialize must reject anything malformed with an error.
#include <span>

#include "relocalization/place_index.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  (void)fleetloc::relocalization::PlaceIndex::Deserialize(
      std::span<const std::uint8_t>(data, size));
  return 0;
}
