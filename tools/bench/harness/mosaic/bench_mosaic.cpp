// One size of `fleetctl bench mosaic`: compose, import and lookup rounds, each in a child process.
#include "harness/mosaic/bench_mosaic.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <filesystem>
#include <functional>
#include <string>

#include "mosaic/importer.h"
#include "runtime/progress_log.h"
#include "support/composed_floor.h"

namespace fleetloc::bench {
namespace {

namespace fs = std::filesystem;

std::string SizeName(cv::Size size) {
  return std::to_string(size.width) + "x" + std::to_string(size.height);
}

void RemoveMosaicFiles(const fs::path& db) {
  std::error_code ec;
  for (const char* suffix : {"", "-wal", "-shm", ".partial", ".partial-wal", ".partial-shm"}) {
    fs::remove(db.string() + suffix, ec);
  }
}

Result<ChildRun> Compose(cv::Size size, const MosaicBenchSettings& settings, const fs::path& pgm) {
  sim::FloorComposerOptions options;
  options.width_px = size.width;
  options.height_px = size.height;
  options.block_px = settings.block_px;
  options.seed = settings.seed;
  spdlog::info("bench mosaic {}: composing {}", SizeName(size), pgm.string());
  return RunInChild([&]() -> Result<std::string> {
    FLEETLOC_RETURN_IF_ERROR(fleetctl::ComposeFloorPgm(settings.photos, options, pgm.string()));
    return std::string();
  });
}

Result<ChildRun> Import(const fs::path& pgm, double resolution_m, const fs::path& db) {
  spdlog::info("bench mosaic: importing {} into {}", pgm.string(), db.string());
  return RunInChild([&]() -> Result<std::string> {
    mosaic::ImportOptions options;
    options.resolution_m = resolution_m;
    runtime::PercentLog progress(
        "import " + (pgm.parent_path().filename() / pgm.filename()).string(), "rows", 5);
    Result<mosaic::MosaicLayout> layout =
        mosaic::ImportImage(pgm.string(), options, db.string(), std::ref(progress));
    if (!layout.ok()) return layout.status();
    return std::string();
  });
}

Result<ChildRun> Lookups(const fs::path& db, const LookupSettings& settings) {
  return RunInChild([&]() -> Result<std::string> {
    Result<LookupRun> run = MeasureLookups(db.string(), settings);
    if (!run.ok()) return run.status();
    return LookupRunJson(*run).dump();
  });
}

}  // namespace

Result<MosaicSizeBench> ComposeAndImport(cv::Size size_px, const MosaicBenchSettings& settings) {
  const fs::path dir = settings.work_dir / SizeName(size_px);
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) return Internal(dir.string() + ": cannot create: " + ec.message());
  MosaicSizeBench bench;
  bench.size_px = size_px;
  bench.pgm = dir / "floor.pgm";
  bench.mosaic = dir / "mosaic.db";
  RemoveMosaicFiles(bench.mosaic);  // ImportImage refuses to overwrite
  Result<ChildRun> compose = Compose(size_px, settings, bench.pgm);
  if (!compose.ok()) return compose.status();
  bench.compose = *compose;
  bench.caller_rss_bytes = ResidentBytes();
  Result<ChildRun> import = Import(bench.pgm, settings.resolution_m, bench.mosaic);
  if (!import.ok()) return import.status();
  bench.import = *import;
  bench.pgm_bytes = fs::file_size(bench.pgm, ec);
  bench.mosaic_bytes = fs::file_size(bench.mosaic, ec);
  return bench;
}

Status AddLookupRound(const MosaicBenchSettings& settings, int round, MosaicSizeBench* bench) {
  LookupSettings lookups = settings.lookups;
  lookups.seed = settings.seed * 1000 + round;
  spdlog::info("bench mosaic {}: lookup round {}", SizeName(bench->size_px), round + 1);
  Result<ChildRun> child = Lookups(bench->mosaic, lookups);
  if (!child.ok()) return child.status();
  Result<LookupRun> run = LookupRunFromJson(nlohmann::json::parse(child->output, nullptr, false));
  if (!run.ok()) return run.status();
  AppendRun(*run, &bench->lookups);
  bench->lookup.wall_s += child->wall_s;
  bench->lookup.user_s += child->user_s;
  bench->lookup.system_s += child->system_s;
  bench->lookup.peak_rss_bytes = std::max(bench->lookup.peak_rss_bytes, child->peak_rss_bytes);
  return Status::Ok();
}

void RemoveSizeFiles(const MosaicBenchSettings& settings, const MosaicSizeBench& bench) {
  if (settings.keep_files) return;
  std::error_code ec;
  fs::remove(bench.pgm, ec);
  RemoveMosaicFiles(bench.mosaic);
}

}  // namespace fleetloc::bench
