// Fuzz target: wire samples from other participants, with every field chosen by the fuzzer — a
// PatchObservation through the map server's DecodePatch (the PNG inside included) and a
// sequence of PlaceIndexChunks through the agent's PlaceIndexAssembler.
#include <fuzzer/FuzzedDataProvider.h>

#include "map_server/patch_decoder.h"
#include "transport/place_index_channel.h"
#include "transport/wire_util.h"

namespace {

using namespace fleetloc;

void FuzzPatch(FuzzedDataProvider& in) {
  fleetloc_PatchObservation p{};
  p.wire_version =
      in.ConsumeBool() ? fleetloc_CURRENT_WIRE_VERSION : in.ConsumeIntegral<std::uint16_t>();
  transport::SetBounded(p.vehicle_id, in.ConsumeRandomLengthString(16));
  p.sequence_number = in.ConsumeIntegral<std::uint64_t>();
  p.stamp = {in.ConsumeIntegral<std::int64_t>(), in.ConsumeIntegral<std::uint32_t>()};
  transport::SetBounded(p.mosaic_id, in.ConsumeBool() ? "fuzz" : in.ConsumeRandomLengthString(70));
  p.mosaic_version = in.ConsumeIntegral<std::int64_t>();
  p.x = in.ConsumeFloatingPoint<double>();
  p.y = in.ConsumeFloatingPoint<double>();
  p.theta = in.ConsumeFloatingPoint<double>();
  for (double& c : p.covariance) c = in.ConsumeFloatingPoint<double>();
  p.quality = in.ConsumeFloatingPoint<float>();
  p.resolution = in.ConsumeBool() ? 0.0005 : in.ConsumeFloatingPoint<double>();
  transport::SetBounded(p.encoding, in.ConsumeBool() ? "png" : in.ConsumeRandomLengthString(20));
  const std::vector<std::uint8_t> image =
      in.ConsumeBytes<std::uint8_t>(in.ConsumeIntegralInRange<std::size_t>(0, 1 << 16));
  p.image = transport::BorrowOctets(image);
  mosaic::MosaicLayout layout;
  layout.mosaic_id = "fuzz";
  layout.width_px = layout.height_px = 1024;
  layout.geo.resolution = 0.0005;
  (void)map_server::DecodePatch(p, layout, {1 << 16, 512});
}

void FuzzChunks(FuzzedDataProvider& in) {
  transport::PlaceIndexAssembler assembler;
  while (in.remaining_bytes() > 0) {
    fleetloc_PlaceIndexChunk c{};
    c.wire_version =
        in.ConsumeBool() ? fleetloc_CURRENT_WIRE_VERSION : in.ConsumeIntegral<std::uint16_t>();
    transport::SetBounded(c.server_id,
                          in.ConsumeBool() ? "ms-1" : in.ConsumeRandomLengthString(12));
    c.chunk = in.ConsumeIntegralInRange<std::uint32_t>(0, 8);
    transport::SetBounded(c.mosaic_id, "fuzz");
    c.mosaic_version = in.ConsumeIntegralInRange<std::int64_t>(0, 3);
    c.generation = in.ConsumeIntegralInRange<std::uint64_t>(0, 3);
    c.chunk_count = in.ConsumeIntegralInRange<std::uint32_t>(0, 8);
    c.blob_bytes = in.ConsumeBool() ? in.ConsumeIntegralInRange<std::uint64_t>(0, 4096)
                                    : in.ConsumeIntegral<std::uint64_t>();
    const std::vector<std::uint8_t> data =
        in.ConsumeBytes<std::uint8_t>(in.ConsumeIntegralInRange<std::size_t>(0, 1024));
    c.data = transport::BorrowOctets(data);
    (void)assembler.Add(c);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzedDataProvider in(data, size);
  if (in.ConsumeBool()) {
    FuzzPatch(in);
  } else {
    FuzzChunks(in);
  }
  return 0;
}
