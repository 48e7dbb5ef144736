// Fuzz target: tile and patch image bytes as they arrive over DDS or from the mosaic file —
// DecodeTile (exact tile size) and DecodeGrayPng (bounded side, header checked before decoding).
#include <span>

#include "mosaic/tile_codec.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace fleetloc;
  const std::span<const std::uint8_t> bytes(data, size);
  (void)mosaic::DecodeTile(bytes, 256);
  (void)mosaic::DecodeGrayPng(bytes, 1024);
  return 0;
}
