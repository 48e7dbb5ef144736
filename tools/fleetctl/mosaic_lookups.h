// `fleetctl bench mosaic`, lookups: latency of reading random tiles of a mosaic by key (PNG bytes
// and decoded) and of assembling tracker-sized blocks at random places through a MosaicView, with
// a new tile cache (cold) and again from the warm cache, as p50/p99 per operation.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <string>

#include "base/status.h"

namespace fleetloc::fleetctl {

struct LookupSettings {
  int tile_samples = 2000;             // random level-0 tiles read, each way
  int block_samples = 300;             // random blocks, each read cold then warm
  cv::Size block_px{700, 560};         // level-0 block size (the tracker's search window)
  std::size_t cache_bytes = 64 << 20;  // tile cache of each view
  std::uint64_t seed = 1;
};

// Latency of one operation over its samples, microseconds.
struct Latency {
  int samples = 0;
  double p50_us = 0, p99_us = 0, mean_us = 0;
};

struct LookupTimes {
  int levels = 0;               // of the mosaic measured
  long long tiles = 0;          // stored tiles, all levels
  std::string query_plan;       // SQLite's plan of the tile lookup (TileStore::TileLookupPlan)
  Latency tile_bytes;           // TileStore::ReadTileBytes
  Latency tile_decoded;         // TileStore::ReadTile (read + PNG decode)
  Latency block_cold;           // MosaicView::ReadBlock with a new, empty tile cache
  Latency block_warm;           // the same block again, all its tiles cached
  long long missing_tiles = 0;  // tiles a block needed that the store lacked (must be 0)
};

// Opens `mosaic_db` read-only and times the lookups with a fixed random seed. NotFound /
// InvalidInput for a missing or broken mosaic; Internal if a tile read fails.
Result<LookupTimes> MeasureLookups(const std::string& mosaic_db, const LookupSettings& settings);

nlohmann::json LookupTimesJson(const LookupTimes& times);
// Reads LookupTimesJson's output back (the measurement runs in a child process). Internal if a
// field is missing or mistyped (a bug: the text is fleetctl's own).
Result<LookupTimes> LookupTimesFromJson(const nlohmann::json& json);

}  // namespace fleetloc::fleetctl
