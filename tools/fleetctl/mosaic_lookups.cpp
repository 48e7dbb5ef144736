// Lookup latency of a mosaic store: random tiles by key and random tracker-sized blocks.
#include "mosaic_lookups.h"

#include <chrono>
#include <memory>
#include <random>
#include <utility>
#include <vector>

#include "mosaic/mosaic_view.h"
#include "mosaic/tile_store.h"
#include "replay/replay.h"

namespace fleetloc::fleetctl {
namespace {

using Clock = std::chrono::steady_clock;

double MicrosecondsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::micro>(Clock::now() - start).count();
}

Latency Summarize(const std::vector<double>& us) {
  Latency latency;
  latency.samples = static_cast<int>(us.size());
  latency.p50_us = replay::Percentile(us, 50);
  latency.p99_us = replay::Percentile(us, 99);
  double sum = 0;
  for (double v : us) sum += v;
  latency.mean_us = us.empty() ? 0 : sum / us.size();
  return latency;
}

// Uniform level-0 tile keys of `layout`, drawn from `rng`.
std::vector<mosaic::TileKey> RandomTiles(const mosaic::MosaicLayout& layout, int count,
                                         std::mt19937_64& rng) {
  std::uniform_int_distribution<int> col(0, mosaic::TileColumns(layout, 0) - 1);
  std::uniform_int_distribution<int> row(0, mosaic::TileRows(layout, 0) - 1);
  std::vector<mosaic::TileKey> keys;
  for (int i = 0; i < count; ++i) keys.push_back({0, col(rng), row(rng)});
  return keys;
}

// Times `read` on every key; Internal on the first failed read.
template <typename Read>
Result<Latency> TimeTileReads(const std::vector<mosaic::TileKey>& keys, Read read) {
  std::vector<double> us;
  for (const mosaic::TileKey& key : keys) {
    const Clock::time_point start = Clock::now();
    const auto tile = read(key);
    us.push_back(MicrosecondsSince(start));
    if (!tile.ok()) return Internal("bench mosaic: " + tile.status().message());
  }
  return Summarize(us);
}

// Random level-0 blocks of `size` inside the mosaic (at the origin if the mosaic is smaller).
std::vector<cv::Rect> RandomBlocks(const mosaic::MosaicLayout& layout, cv::Size size, int count,
                                   std::mt19937_64& rng) {
  std::uniform_int_distribution<int> x(0, std::max(0, layout.width_px - size.width));
  std::uniform_int_distribution<int> y(0, std::max(0, layout.height_px - size.height));
  std::vector<cv::Rect> blocks;
  for (int i = 0; i < count; ++i) blocks.emplace_back(cv::Point(x(rng), y(rng)), size);
  return blocks;
}

// Each block read through a view with a new cache (cold), then again from that cache (warm).
void TimeBlocks(const std::shared_ptr<mosaic::TileStore>& store,
                const std::vector<cv::Rect>& blocks, std::size_t cache_bytes, LookupTimes* times) {
  std::vector<double> cold_us, warm_us;
  for (const cv::Rect& block : blocks) {
    mosaic::MosaicView view(store->layout(), mosaic::MakeTileLoader(store),
                            std::make_shared<mosaic::TileCache>(cache_bytes));
    Clock::time_point start = Clock::now();
    cv::Mat pixels = view.ReadBlock(0, block);
    cold_us.push_back(MicrosecondsSince(start));
    start = Clock::now();
    pixels = view.ReadBlock(0, block);
    warm_us.push_back(MicrosecondsSince(start));
    times->missing_tiles += view.missing_tiles() + view.unreadable_tiles();
  }
  times->block_cold = Summarize(cold_us);
  times->block_warm = Summarize(warm_us);
}

nlohmann::json LatencyJson(const Latency& l) {
  return {
      {"samples", l.samples}, {"p50_us", l.p50_us}, {"p99_us", l.p99_us}, {"mean_us", l.mean_us}};
}

Latency LatencyFromJson(const nlohmann::json& j) {
  return {j.at("samples").get<int>(), j.at("p50_us").get<double>(), j.at("p99_us").get<double>(),
          j.at("mean_us").get<double>()};
}

}  // namespace

Result<LookupTimes> MeasureLookups(const std::string& mosaic_db, const LookupSettings& settings) {
  Result<std::unique_ptr<mosaic::TileStore>> opened =
      mosaic::TileStore::Open(mosaic_db, mosaic::OpenMode::kReadOnly);
  if (!opened.ok()) return opened.status();
  const std::shared_ptr<mosaic::TileStore> store = std::move(opened).value();
  LookupTimes times;
  Result<std::string> plan = store->TileLookupPlan();
  if (!plan.ok()) return plan.status();
  times.query_plan = *plan;
  Result<std::vector<long long>> counts = store->TileCountsPerLevel();
  if (!counts.ok()) return counts.status();
  for (long long count : *counts) times.tiles += count;
  std::mt19937_64 rng(settings.seed);
  const mosaic::MosaicLayout layout = store->layout();
  times.levels = layout.levels;
  Result<Latency> bytes = TimeTileReads(RandomTiles(layout, settings.tile_samples, rng),
                                        [&](const auto& key) { return store->ReadTileBytes(key); });
  if (!bytes.ok()) return bytes.status();
  times.tile_bytes = *bytes;
  Result<Latency> decoded = TimeTileReads(RandomTiles(layout, settings.tile_samples, rng),
                                          [&](const auto& key) { return store->ReadTile(key); });
  if (!decoded.ok()) return decoded.status();
  times.tile_decoded = *decoded;
  TimeBlocks(store, RandomBlocks(layout, settings.block_px, settings.block_samples, rng),
             settings.cache_bytes, &times);
  return times;
}

nlohmann::json LookupTimesJson(const LookupTimes& times) {
  return {{"levels", times.levels},
          {"tiles", times.tiles},
          {"query_plan", times.query_plan},
          {"tile_bytes", LatencyJson(times.tile_bytes)},
          {"tile_decoded", LatencyJson(times.tile_decoded)},
          {"block_cold", LatencyJson(times.block_cold)},
          {"block_warm", LatencyJson(times.block_warm)},
          {"missing_tiles", times.missing_tiles}};
}

Result<LookupTimes> LookupTimesFromJson(const nlohmann::json& json) {
  try {
    LookupTimes times;
    times.levels = json.at("levels").get<int>();
    times.tiles = json.at("tiles").get<long long>();
    times.query_plan = json.at("query_plan").get<std::string>();
    times.tile_bytes = LatencyFromJson(json.at("tile_bytes"));
    times.tile_decoded = LatencyFromJson(json.at("tile_decoded"));
    times.block_cold = LatencyFromJson(json.at("block_cold"));
    times.block_warm = LatencyFromJson(json.at("block_warm"));
    times.missing_tiles = json.at("missing_tiles").get<long long>();
    return times;
  } catch (const nlohmann::json::exception& e) {
    return Internal(std::string("bench mosaic: lookup results: ") + e.what());
  }
}

}  // namespace fleetloc::fleetctl
