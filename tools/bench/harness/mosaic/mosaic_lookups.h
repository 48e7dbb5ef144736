// `fleetctl bench mosaic`, lookups: latency of reading random tiles of a mosaic by key (PNG bytes
// and decoded) and of assembling tracker-sized blocks at random places through a MosaicView, with
// a new tile cache (cold) and again from the warm cache; summarized as p50/p99 per operation.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "base/status.h"

namespace fleetloc::bench {

struct LookupSettings {
  int tile_samples = 400;              // random level-0 tiles read, each way
  int block_samples = 60;              // random blocks, each read cold then warm
  cv::Size block_px{700, 560};         // level-0 block size (the tracker's search window)
  std::size_t cache_bytes = 64 << 20;  // tile cache of each view
  std::uint64_t seed = 1;
};

// Time of every operation timed, microseconds.
struct LookupSamples {
  std::vector<double> tile_bytes;    // TileStore::ReadTileBytes
  std::vector<double> tile_decoded;  // TileStore::ReadTile (read + PNG decode)
  std::vector<double> block_cold;    // MosaicView::ReadBlock with a new, empty tile cache
  std::vector<double> block_warm;    // the same block again, all its tiles cached
};

// One measurement over one mosaic.
struct LookupRun {
  int levels = 0;          // of the mosaic measured
  long long tiles = 0;     // stored tiles, all levels
  std::string query_plan;  // SQLite's plan of the tile lookup (TileStore::TileLookupPlan)
  LookupSamples samples;
  long long missing_tiles = 0;  // tiles a block needed that the store lacked (must be 0)
};

// Opens `mosaic_db` read-only and times the lookups, drawing places from `settings.seed`.
// NotFound / InvalidInput for a missing or broken mosaic; Internal if a tile read fails.
Result<LookupRun> MeasureLookups(const std::string& mosaic_db, const LookupSettings& settings);

// Adds `more`'s samples and missing tiles to `all` and takes its mosaic facts.
void AppendRun(const LookupRun& more, LookupRun* all);

// Latency of one operation over its samples.
struct Latency {
  int samples = 0;
  double p50_us = 0, p99_us = 0, mean_us = 0;
};
Latency Summarize(const std::vector<double>& us);

struct LookupLatencies {
  Latency tile_bytes, tile_decoded, block_cold, block_warm;
};
LookupLatencies Summarize(const LookupSamples& samples);

nlohmann::json LookupRunJson(const LookupRun& run);
// Reads LookupRunJson's output back (the measurement runs in a child process). Internal if a field
// is missing or mistyped (a bug: the text is fleetctl's own).
Result<LookupRun> LookupRunFromJson(const nlohmann::json& json);

}  // namespace fleetloc::bench
