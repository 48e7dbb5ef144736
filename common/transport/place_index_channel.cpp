// Chunking, publishing and reassembling a place index over DDS (see place_index_channel.h).
#include "transport/place_index_channel.h"

#include <algorithm>
#include <chrono>

#include "transport/topic_names.h"
#include "transport/wire_util.h"

namespace fleetloc::transport {

namespace {
const std::optional<PlaceIndexBlob> kNothingYet;
}  // namespace

Status PlaceIndexAssembler::Check(const fleetloc_PlaceIndexChunk& c) {
  if (c.wire_version != fleetloc_CURRENT_WIRE_VERSION) {
    return InvalidInput("place index chunk of wire version " + std::to_string(c.wire_version));
  }
  if (!IsValidEntityId(GetBounded(c.server_id))) {
    return InvalidInput("place index chunk from an invalid server id");
  }
  if (c.blob_bytes == 0 || c.blob_bytes > kMaxPlaceIndexBytes) {
    return InvalidInput("place index of " + std::to_string(c.blob_bytes) + " bytes (at most " +
                        std::to_string(kMaxPlaceIndexBytes) + ")");
  }
  if (c.chunk_count == 0 || c.chunk_count > c.blob_bytes || c.chunk >= c.chunk_count) {
    return InvalidInput("place index chunk " + std::to_string(c.chunk) + " of " +
                        std::to_string(c.chunk_count));
  }
  if (c.data._length == 0 || c.data._length > c.blob_bytes) {
    return InvalidInput("place index chunk of " + std::to_string(c.data._length) + " bytes");
  }
  return Status::Ok();
}

Status PlaceIndexAssembler::CheckSameIndex(const Partial& p, const fleetloc_PlaceIndexChunk& c) {
  if (GetBounded(c.mosaic_id) != p.blob.mosaic_id || c.mosaic_version != p.blob.mosaic_version ||
      c.chunk_count != p.chunk_count || c.blob_bytes != p.blob_bytes) {
    return InvalidInput("place index chunks of generation " + std::to_string(c.generation) +
                        " disagree on mosaic, version, count or size");
  }
  if (p.bytes_received + c.data._length > p.blob_bytes) {
    return InvalidInput("place index chunks hold more than its " + std::to_string(p.blob_bytes) +
                        " bytes");
  }
  return Status::Ok();
}

PlaceIndexBlob PlaceIndexAssembler::Concatenate(Partial* p) {
  PlaceIndexBlob blob = std::move(p->blob);
  blob.bytes.reserve(p->blob_bytes);
  for (auto& chunk : p->chunks) blob.bytes.insert(blob.bytes.end(), chunk->begin(), chunk->end());
  return blob;
}

Result<std::optional<PlaceIndexBlob>> PlaceIndexAssembler::Add(const fleetloc_PlaceIndexChunk& c) {
  FLEETLOC_RETURN_IF_ERROR(Check(c));
  const std::string server = GetBounded(c.server_id);
  if (auto done = completed_.find(server);
      done != completed_.end() && c.generation <= done->second) {
    return kNothingYet;
  }
  auto found = partial_.find(server);
  if (found != partial_.end() && c.generation < found->second.blob.generation) return kNothingYet;
  if (found == partial_.end() || c.generation > found->second.blob.generation) {
    Partial fresh;
    fresh.blob = {server, GetBounded(c.mosaic_id), c.mosaic_version, c.generation, {}};
    fresh.chunk_count = c.chunk_count;
    fresh.blob_bytes = c.blob_bytes;
    fresh.chunks.resize(c.chunk_count);
    found = partial_.insert_or_assign(server, std::move(fresh)).first;
  }
  Partial& p = found->second;
  FLEETLOC_RETURN_IF_ERROR(CheckSameIndex(p, c));
  if (p.chunks[c.chunk]) return kNothingYet;  // a repeat (durable history re-sent)
  const std::span<const std::uint8_t> data = OctetSpan(c.data);
  p.chunks[c.chunk].emplace(data.begin(), data.end());
  p.bytes_received += data.size();
  if (++p.chunks_received < p.chunk_count) return kNothingYet;
  if (p.bytes_received != p.blob_bytes) {
    partial_.erase(found);
    return InvalidInput("place index chunks hold fewer bytes than the index's");
  }
  PlaceIndexBlob blob = Concatenate(&p);
  completed_[server] = blob.generation;
  partial_.erase(found);
  return std::optional<PlaceIndexBlob>(std::move(blob));
}

PlaceIndexPublisher::PlaceIndexPublisher(std::string server_id,
                                         Topic<fleetloc_PlaceIndexChunk> topic,
                                         Writer<fleetloc_PlaceIndexChunk> writer)
    : server_id_(std::move(server_id)), topic_(std::move(topic)), writer_(std::move(writer)) {}

Result<std::unique_ptr<PlaceIndexPublisher>> PlaceIndexPublisher::Create(
    const Participant& participant, const std::string& server_id) {
  if (!IsValidEntityId(server_id)) {
    return InvalidInput("server id '" + server_id + "' is not 1-11 of [A-Za-z0-9_-]");
  }
  auto topic = Topic<fleetloc_PlaceIndexChunk>::Create(participant, topics::kPlaceIndex);
  if (!topic.ok()) return topic.status();
  auto writer =
      Writer<fleetloc_PlaceIndexChunk>::Create(participant.get(), *topic, DurableStateQos(1));
  if (!writer.ok()) return writer.status();
  return std::unique_ptr<PlaceIndexPublisher>(
      new PlaceIndexPublisher(server_id, std::move(topic).value(), std::move(writer).value()));
}

Status PlaceIndexPublisher::Publish(const std::string& mosaic_id, long long mosaic_version,
                                    std::span<const std::uint8_t> blob) {
  if (blob.empty() || blob.size() > kMaxPlaceIndexBytes) {
    return InvalidInput("place index of " + std::to_string(blob.size()) + " bytes");
  }
  fleetloc_PlaceIndexChunk chunk{};
  chunk.wire_version = fleetloc_CURRENT_WIRE_VERSION;
  SetBounded(chunk.server_id, server_id_);
  SetBounded(chunk.mosaic_id, mosaic_id);
  chunk.mosaic_version = mosaic_version;
  chunk.generation = static_cast<std::uint64_t>(
      std::chrono::system_clock::now().time_since_epoch() / std::chrono::nanoseconds(1));
  const std::size_t count = (blob.size() + kPlaceIndexChunkBytes - 1) / kPlaceIndexChunkBytes;
  chunk.chunk_count = static_cast<std::uint32_t>(count);
  chunk.blob_bytes = blob.size();
  for (std::size_t i = 0; i < count; ++i) {
    const std::size_t begin = i * kPlaceIndexChunkBytes;
    chunk.chunk = static_cast<std::uint32_t>(i);
    chunk.data =
        BorrowOctets(blob.subspan(begin, std::min(kPlaceIndexChunkBytes, blob.size() - begin)));
    FLEETLOC_RETURN_IF_ERROR(writer_.Write(chunk));
  }
  // The previous generation's chunks beyond the new count would stay in the durable history.
  fleetloc_PlaceIndexChunk key{};
  SetBounded(key.server_id, server_id_);
  for (std::uint32_t stale = chunk.chunk_count; stale < published_chunks_; ++stale) {
    key.chunk = stale;
    FLEETLOC_RETURN_IF_ERROR(writer_.Unregister(key));
  }
  published_chunks_ = chunk.chunk_count;
  return Status::Ok();
}

PlaceIndexReceiver::PlaceIndexReceiver(Topic<fleetloc_PlaceIndexChunk> topic,
                                       Reader<fleetloc_PlaceIndexChunk> reader)
    : topic_(std::move(topic)), reader_(std::move(reader)) {}

Result<std::unique_ptr<PlaceIndexReceiver>> PlaceIndexReceiver::Create(
    const Participant& participant) {
  auto topic = Topic<fleetloc_PlaceIndexChunk>::Create(participant, topics::kPlaceIndex);
  if (!topic.ok()) return topic.status();
  auto reader =
      Reader<fleetloc_PlaceIndexChunk>::Create(participant.get(), *topic, DurableStateQos(1));
  if (!reader.ok()) return reader.status();
  return std::unique_ptr<PlaceIndexReceiver>(
      new PlaceIndexReceiver(std::move(topic).value(), std::move(reader).value()));
}

std::vector<PlaceIndexBlob> PlaceIndexReceiver::Poll() {
  std::vector<PlaceIndexBlob> done;
  const Result<int> taken =
      reader_.TakeAll([&](const fleetloc_PlaceIndexChunk& chunk, const dds_sample_info_t&) {
        Result<std::optional<PlaceIndexBlob>> added = assembler_.Add(chunk);
        if (!added.ok()) {
          ++rejected_;
          last_error_ = added.status().message();
        } else if (added->has_value()) {
          done.push_back(std::move(**added));
        }
      });
  if (!taken.ok()) {
    ++rejected_;
    last_error_ = taken.status().message();
  }
  return done;
}

}  // namespace fleetloc::transport
