// Lookup latency of a mosaic store: random tiles by key and random tracker-sized blocks.
#include "harness/mosaic/mosaic_lookups.h"

#include <chrono>
#include <memory>
#include <random>
#include <utility>
#include <vector>

#include "mosaic/mosaic_view.h"
#include "mosaic/tile_store.h"
#include "replay/replay.h"

namespace fleetloc::bench {
namespace {

using Clock = std::chrono::steady_clock;

double MicrosecondsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::micro>(Clock::now() - start).count();
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

// Times `read` on every key into `us`; Internal on the first failed read.
template <typename Read>
Status TimeTileReads(const std::vector<mosaic::TileKey>& keys, Read read, std::vector<double>* us) {
  for (const mosaic::TileKey& key : keys) {
    const Clock::time_point start = Clock::now();
    const auto tile = read(key);
    us->push_back(MicrosecondsSince(start));
    if (!tile.ok()) return Internal("bench mosaic: " + tile.status().message());
  }
  return Status::Ok();
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
                const std::vector<cv::Rect>& blocks, std::size_t cache_bytes, LookupRun* run) {
  for (const cv::Rect& block : blocks) {
    mosaic::MosaicView view(store->layout(), mosaic::MakeTileLoader(store),
                            std::make_shared<mosaic::TileCache>(cache_bytes));
    Clock::time_point start = Clock::now();
    cv::Mat pixels = view.ReadBlock(0, block);
    run->samples.block_cold.push_back(MicrosecondsSince(start));
    start = Clock::now();
    pixels = view.ReadBlock(0, block);
    run->samples.block_warm.push_back(MicrosecondsSince(start));
    run->missing_tiles += view.missing_tiles() + view.unreadable_tiles();
  }
}

}  // namespace

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

LookupLatencies Summarize(const LookupSamples& samples) {
  return {Summarize(samples.tile_bytes), Summarize(samples.tile_decoded),
          Summarize(samples.block_cold), Summarize(samples.block_warm)};
}

Result<LookupRun> MeasureLookups(const std::string& mosaic_db, const LookupSettings& settings) {
  Result<std::unique_ptr<mosaic::TileStore>> opened =
      mosaic::TileStore::Open(mosaic_db, mosaic::OpenMode::kReadOnly);
  if (!opened.ok()) return opened.status();
  const std::shared_ptr<mosaic::TileStore> store = std::move(opened).value();
  LookupRun run;
  Result<std::string> plan = store->TileLookupPlan();
  if (!plan.ok()) return plan.status();
  run.query_plan = *plan;
  Result<std::vector<long long>> counts = store->TileCountsPerLevel();
  if (!counts.ok()) return counts.status();
  for (long long count : *counts) run.tiles += count;
  const mosaic::MosaicLayout layout = store->layout();
  run.levels = layout.levels;
  std::mt19937_64 rng(settings.seed);
  FLEETLOC_RETURN_IF_ERROR(TimeTileReads(
      RandomTiles(layout, settings.tile_samples, rng),
      [&](const auto& key) { return store->ReadTileBytes(key); }, &run.samples.tile_bytes));
  FLEETLOC_RETURN_IF_ERROR(TimeTileReads(
      RandomTiles(layout, settings.tile_samples, rng),
      [&](const auto& key) { return store->ReadTile(key); }, &run.samples.tile_decoded));
  TimeBlocks(store, RandomBlocks(layout, settings.block_px, settings.block_samples, rng),
             settings.cache_bytes, &run);
  return run;
}

void AppendRun(const LookupRun& more, LookupRun* all) {
  all->levels = more.levels;
  all->tiles = more.tiles;
  all->query_plan = more.query_plan;
  const auto append = [](const std::vector<double>& from, std::vector<double>* to) {
    to->insert(to->end(), from.begin(), from.end());
  };
  append(more.samples.tile_bytes, &all->samples.tile_bytes);
  append(more.samples.tile_decoded, &all->samples.tile_decoded);
  append(more.samples.block_cold, &all->samples.block_cold);
  append(more.samples.block_warm, &all->samples.block_warm);
  all->missing_tiles += more.missing_tiles;
}

nlohmann::json LookupRunJson(const LookupRun& run) {
  return {{"levels", run.levels},
          {"tiles", run.tiles},
          {"query_plan", run.query_plan},
          {"tile_bytes_us", run.samples.tile_bytes},
          {"tile_decoded_us", run.samples.tile_decoded},
          {"block_cold_us", run.samples.block_cold},
          {"block_warm_us", run.samples.block_warm},
          {"missing_tiles", run.missing_tiles}};
}

Result<LookupRun> LookupRunFromJson(const nlohmann::json& json) {
  try {
    LookupRun run;
    run.levels = json.at("levels").get<int>();
    run.tiles = json.at("tiles").get<long long>();
    run.query_plan = json.at("query_plan").get<std::string>();
    run.samples.tile_bytes = json.at("tile_bytes_us").get<std::vector<double>>();
    run.samples.tile_decoded = json.at("tile_decoded_us").get<std::vector<double>>();
    run.samples.block_cold = json.at("block_cold_us").get<std::vector<double>>();
    run.samples.block_warm = json.at("block_warm_us").get<std::vector<double>>();
    run.missing_tiles = json.at("missing_tiles").get<long long>();
    return run;
  } catch (const nlohmann::json::exception& e) {
    return Internal(std::string("bench mosaic: lookup results: ") + e.what());
  }
}

}  // namespace fleetloc::bench
