// Mosaic tiles for the dashboard's overview map, fetched from the map server over DDS with a
// TileClient in the supervisor's own partition (fleetloc.vehicle.<supervisor_id>), kept in a
// bounded LRU of encoded PNGs and dropped when the mosaic version changes. HTTP threads call Get
// (it blocks until the tile arrives or the time-out); the supervisor's DDS thread calls Pump.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <list>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "mosaic/tile_key.h"
#include "transport/tile_client.h"

namespace fleetloc::fleet_supervisor {

struct TileAnswer {
  enum class Outcome { kOk, kOutOfRange, kNoMosaic, kTimeout, kError };
  Outcome outcome = Outcome::kError;
  std::shared_ptr<const std::vector<std::uint8_t>> png;  // when kOk
  std::string error;
  long long version = 0;
};

class OverviewTiles {
 public:
  OverviewTiles(std::unique_ptr<transport::TileClient> client, size_t cache_bytes,
                std::chrono::milliseconds timeout, int min_level);

  // Takes the tiles and mosaic announcements received since the last call (DDS thread).
  void Pump();
  // The mosaic the map server announces, if any.
  std::optional<mosaic::MosaicLayout> Layout() const;
  // The tile from the cache, or requested and waited for (up to the time-out). kOutOfRange for a
  // level below min_level or outside the grid; kNoMosaic before a map server announced one.
  TileAnswer Get(const mosaic::TileKey& key);
  dds_entity_t tile_reader() const { return client_->tile_reader(); }
  bool ServerMatched() const;

 private:
  struct Entry {
    std::shared_ptr<const std::vector<std::uint8_t>> png;
    std::list<mosaic::TileKey>::iterator lru;
  };
  void PumpLocked();
  void Insert(const mosaic::TileKey& key, std::vector<std::uint8_t> png);

  mutable std::mutex mutex_;
  std::condition_variable arrived_;
  std::unique_ptr<transport::TileClient> client_;
  size_t cache_bytes_;
  std::chrono::milliseconds timeout_;
  int min_level_;
  std::optional<mosaic::MosaicLayout> layout_;
  std::map<mosaic::TileKey, Entry> cache_;
  std::list<mosaic::TileKey> lru_;  // most recent first
  size_t bytes_ = 0;
  std::set<mosaic::TileKey> in_flight_;
  std::map<mosaic::TileKey, std::string> failed_;  // answered with an error status
  uint32_t next_request_ = 1;
};

}  // namespace fleetloc::fleet_supervisor
