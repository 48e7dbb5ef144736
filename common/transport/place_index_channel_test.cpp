// The place index channel: chunk reassembly (order, repeats, generations, bad chunks) and the
// DDS round trip from a publisher to a receiver that joins late, through a shorter new index.
#include "transport/place_index_channel.h"

#include <gtest/gtest.h>

#include <chrono>
#include <numeric>
#include <thread>

#include "transport/wire_util.h"

namespace fleetloc::transport {
namespace {

constexpr uint32_t kDomain = 72;  // this test binary's own domain

std::vector<std::uint8_t> Bytes(std::size_t n, std::uint8_t seed) {
  std::vector<std::uint8_t> bytes(n);
  for (std::size_t i = 0; i < n; ++i) bytes[i] = static_cast<std::uint8_t>(seed + i * 7 + i / 251);
  return bytes;
}

// Chunk `i` of `count` over `blob` (equal slices, the last one shorter).
fleetloc_PlaceIndexChunk ChunkOf(const std::vector<std::uint8_t>& blob, std::uint32_t i,
                                 std::uint32_t count, std::uint64_t generation,
                                 const char* server = "ms-1") {
  fleetloc_PlaceIndexChunk c{};
  c.wire_version = fleetloc_CURRENT_WIRE_VERSION;
  SetBounded(c.server_id, server);
  SetBounded(c.mosaic_id, "floor");
  c.mosaic_version = 3;
  c.generation = generation;
  c.chunk = i;
  c.chunk_count = count;
  c.blob_bytes = blob.size();
  const std::size_t slice = (blob.size() + count - 1) / count;
  const std::size_t begin = std::min<std::size_t>(i * slice, blob.size());
  c.data = BorrowOctets(std::span(blob).subspan(begin, std::min(slice, blob.size() - begin)));
  return c;
}

TEST(PlaceIndexAssembler, ReassemblesChunksInAnyOrderIgnoringRepeats) {
  const std::vector<std::uint8_t> blob = Bytes(1000, 1);
  PlaceIndexAssembler assembler;
  for (std::uint32_t i : {3u, 0u, 3u, 2u}) {
    auto added = assembler.Add(ChunkOf(blob, i, 4, 10));
    ASSERT_TRUE(added.ok()) << added.status().message();
    EXPECT_FALSE(added->has_value());
  }
  auto done = assembler.Add(ChunkOf(blob, 1, 4, 10));
  ASSERT_TRUE(done.ok() && done->has_value());
  EXPECT_EQ((*done)->bytes, blob);
  EXPECT_EQ((*done)->server_id, "ms-1");
  EXPECT_EQ((*done)->mosaic_id, "floor");
  EXPECT_EQ((*done)->mosaic_version, 3);
  // The durable history sent again completes nothing.
  for (std::uint32_t i = 0; i < 4; ++i)
    EXPECT_FALSE(assembler.Add(ChunkOf(blob, i, 4, 10))->has_value());
}

TEST(PlaceIndexAssembler, ANewerGenerationReplacesAnUnfinishedOneAndOlderChunksAreIgnored) {
  const std::vector<std::uint8_t> old_blob = Bytes(900, 2), new_blob = Bytes(500, 3);
  PlaceIndexAssembler assembler;
  ASSERT_TRUE(assembler.Add(ChunkOf(old_blob, 0, 3, 10)).ok());
  ASSERT_FALSE(assembler.Add(ChunkOf(new_blob, 0, 2, 11))->has_value());
  EXPECT_FALSE(assembler.Add(ChunkOf(old_blob, 1, 3, 10))->has_value());  // older: ignored
  EXPECT_FALSE(assembler.Add(ChunkOf(old_blob, 2, 3, 10))->has_value());
  auto done = assembler.Add(ChunkOf(new_blob, 1, 2, 11));
  ASSERT_TRUE(done.ok() && done->has_value());
  EXPECT_EQ((*done)->bytes, new_blob);
  EXPECT_EQ((*done)->generation, 11u);
  // Another server's index is collected on its own.
  auto other = assembler.Add(ChunkOf(old_blob, 0, 1, 5, "ms-2"));
  ASSERT_TRUE(other.ok() && other->has_value());
  EXPECT_EQ((*other)->server_id, "ms-2");
}

TEST(PlaceIndexAssembler, RejectsChunksThatCannotBelongToAnIndex) {
  const std::vector<std::uint8_t> blob = Bytes(100, 4);
  auto rejected = [](fleetloc_PlaceIndexChunk c, const std::string& what) {
    PlaceIndexAssembler assembler;
    auto added = assembler.Add(c);
    ASSERT_FALSE(added.ok()) << what;
    EXPECT_EQ(added.status().code(), StatusCode::kInvalidInput) << what;
  };
  fleetloc_PlaceIndexChunk c = ChunkOf(blob, 0, 2, 1);
  c.wire_version = 99;
  rejected(c, "wire version");
  c = ChunkOf(blob, 0, 2, 1);
  c.chunk = 2;
  rejected(c, "chunk beyond the count");
  c = ChunkOf(blob, 0, 2, 1);
  c.chunk_count = 0;
  rejected(c, "no chunks");
  c = ChunkOf(blob, 0, 2, 1);
  c.blob_bytes = kMaxPlaceIndexBytes + 1;
  rejected(c, "oversized");
  c = ChunkOf(blob, 0, 2, 1);
  c.blob_bytes = 10;
  rejected(c, "more data than the index");
  c = ChunkOf(blob, 0, 2, 1);
  SetBounded(c.server_id, "ms*");
  rejected(c, "wildcard server id");
  // Chunks of one generation that disagree.
  PlaceIndexAssembler assembler;
  ASSERT_TRUE(assembler.Add(ChunkOf(blob, 0, 2, 1)).ok());
  c = ChunkOf(blob, 1, 2, 1);
  c.mosaic_version = 4;
  EXPECT_FALSE(assembler.Add(c).ok());
  // Chunks whose sizes do not add up to the index's.
  PlaceIndexAssembler short_chunks;
  c = ChunkOf(blob, 0, 2, 1);
  c.data._length = 10;
  ASSERT_TRUE(short_chunks.Add(c).ok());
  EXPECT_FALSE(short_chunks.Add(ChunkOf(blob, 1, 2, 1)).ok());
}

// Polls the receiver for up to 10 s until an index arrives.
std::optional<PlaceIndexBlob> Receive(PlaceIndexReceiver& receiver) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (std::chrono::steady_clock::now() < end) {
    std::vector<PlaceIndexBlob> done = receiver.Poll();
    if (!done.empty()) return std::move(done.back());
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return std::nullopt;
}

TEST(PlaceIndexChannel, ALateReceiverGetsTheWholeIndexThenAShorterNewOne) {
  auto server = Participant::Create(kDomain);
  ASSERT_TRUE(server.ok()) << server.status().message();
  auto publisher = PlaceIndexPublisher::Create(*server, "ms-1");
  ASSERT_TRUE(publisher.ok()) << publisher.status().message();
  const std::vector<std::uint8_t> big = Bytes(3 * kPlaceIndexChunkBytes + 12345, 5);
  ASSERT_TRUE((*publisher)->Publish("floor", 1, big).ok());
  // Joins after the publication: the durable history brings every chunk.
  auto vehicle = Participant::Create(kDomain);
  ASSERT_TRUE(vehicle.ok());
  auto receiver = PlaceIndexReceiver::Create(*vehicle);
  ASSERT_TRUE(receiver.ok()) << receiver.status().message();
  std::optional<PlaceIndexBlob> got = Receive(**receiver);
  ASSERT_TRUE(got.has_value());
  EXPECT_EQ(got->bytes, big);
  EXPECT_EQ(got->mosaic_version, 1);
  const std::vector<std::uint8_t> small = Bytes(1000, 6);
  ASSERT_TRUE((*publisher)->Publish("floor", 2, small).ok());
  got = Receive(**receiver);
  ASSERT_TRUE(got.has_value());
  EXPECT_EQ(got->bytes, small);
  EXPECT_EQ(got->mosaic_version, 2);
  EXPECT_EQ((*receiver)->rejected(), 0u);
  // A receiver joining now gets only the new, one-chunk index (the stale chunks were unregistered).
  auto late = PlaceIndexReceiver::Create(*vehicle);
  ASSERT_TRUE(late.ok());
  got = Receive(**late);
  ASSERT_TRUE(got.has_value());
  EXPECT_EQ(got->bytes, small);
  EXPECT_TRUE(PlaceIndexPublisher::Create(*server, "bad id").status().code() ==
              StatusCode::kInvalidInput);
}

}  // namespace
}  // namespace fleetloc::transport
