// The place index over DDS (topic fleetloc/place_index): a map server publishes the serialized
// index of the mosaic version it serves, cut into chunks, durably (PlaceIndexPublisher); a vehicle
// takes the chunks as they come and reassembles whole indexes (PlaceIndexReceiver, whose logic is
// PlaceIndexAssembler). Bytes only: what the blob means, and its checksum, are
// relocalization::PlaceIndex's business.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "transport/typed_io.h"

namespace fleetloc::transport {

// The chunk size the publisher cuts (receivers take any size: chunks are placed by index).
inline constexpr std::size_t kPlaceIndexChunkBytes = 256 << 10;
// The largest index a receiver accepts (the 108-megapixel bench mosaic's is ~9 MB).
inline constexpr std::uint64_t kMaxPlaceIndexBytes = std::uint64_t{1} << 30;

struct PlaceIndexBlob {
  std::string server_id;
  std::string mosaic_id;
  long long mosaic_version = 0;
  std::uint64_t generation = 0;
  std::vector<std::uint8_t> bytes;
};

// Collects chunks per server; a newer generation of a server replaces its unfinished older one,
// and chunks of a generation older than the one being collected, or of one already completed,
// are ignored (a durable writer re-sends its history to each new reader).
class PlaceIndexAssembler {
 public:
  // The whole index when `chunk` completes one, else nullopt. InvalidInput naming the problem
  // for a chunk that cannot belong to any index (unknown wire version, bad server id, chunk
  // number or count out of range, size over the limit, more data than the index holds, a
  // generation's chunks disagreeing on mosaic, version, count or size).
  Result<std::optional<PlaceIndexBlob>> Add(const fleetloc_PlaceIndexChunk& chunk);

 private:
  struct Partial {
    PlaceIndexBlob blob;  // bytes filled in at completion
    std::uint32_t chunk_count = 0;
    std::uint64_t blob_bytes = 0;
    std::uint64_t bytes_received = 0;
    std::vector<std::optional<std::vector<std::uint8_t>>> chunks;
    std::uint32_t chunks_received = 0;
  };
  static Status Check(const fleetloc_PlaceIndexChunk& chunk);
  static Status CheckSameIndex(const Partial& partial, const fleetloc_PlaceIndexChunk& chunk);
  static PlaceIndexBlob Concatenate(Partial* partial);

  std::map<std::string, Partial> partial_;          // by server id
  std::map<std::string, std::uint64_t> completed_;  // newest generation done, by server id
};

class PlaceIndexPublisher {
 public:
  static Result<std::unique_ptr<PlaceIndexPublisher>> Create(const Participant& participant,
                                                             const std::string& server_id);
  // Publishes `blob` as a new generation (wall-clock nanoseconds, so it is newer than anything a
  // previous run of this server published) and unregisters the previous generation's chunks
  // beyond the new count.
  Status Publish(const std::string& mosaic_id, long long mosaic_version,
                 std::span<const std::uint8_t> blob);
  int MatchedReaders() const { return writer_.MatchedReaders(); }

 private:
  PlaceIndexPublisher(std::string server_id, Topic<fleetloc_PlaceIndexChunk> topic,
                      Writer<fleetloc_PlaceIndexChunk> writer);
  std::string server_id_;
  Topic<fleetloc_PlaceIndexChunk> topic_;
  Writer<fleetloc_PlaceIndexChunk> writer_;
  std::uint32_t published_chunks_ = 0;
};

class PlaceIndexReceiver {
 public:
  static Result<std::unique_ptr<PlaceIndexReceiver>> Create(const Participant& participant);
  // The indexes completed by the chunks that arrived since the last call (usually none). Chunks
  // that cannot belong to an index are dropped and counted.
  std::vector<PlaceIndexBlob> Poll();
  std::uint64_t rejected() const { return rejected_; }
  const std::string& last_error() const { return last_error_; }

 private:
  PlaceIndexReceiver(Topic<fleetloc_PlaceIndexChunk> topic,
                     Reader<fleetloc_PlaceIndexChunk> reader);
  Topic<fleetloc_PlaceIndexChunk> topic_;
  Reader<fleetloc_PlaceIndexChunk> reader_;
  PlaceIndexAssembler assembler_;
  std::uint64_t rejected_ = 0;
  std::string last_error_;
};

}  // namespace fleetloc::transport
