// One size of `fleetctl bench mosaic`: compose, import and look up, each in a child process.
#include "bench_mosaic.h"

#include <spdlog/spdlog.h>

#include <filesystem>
#include <string>

#include "composed_floor.h"
#include "mosaic/importer.h"
#include "progress_log.h"

namespace fleetloc::fleetctl {
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
    FLEETLOC_RETURN_IF_ERROR(ComposeFloorPgm(settings.photos, options, pgm.string()));
    return std::string();
  });
}

Result<ChildRun> Import(const fs::path& pgm, double resolution_m, const fs::path& db) {
  spdlog::info("bench mosaic: importing {} into {}", pgm.string(), db.string());
  return RunInChild([&]() -> Result<std::string> {
    mosaic::ImportOptions options;
    options.resolution_m = resolution_m;
    PercentLog progress("import " + pgm.filename().string(), "rows", 5);
    Result<mosaic::MosaicLayout> layout =
        mosaic::ImportImage(pgm.string(), options, db.string(), std::ref(progress));
    if (!layout.ok()) return layout.status();
    return std::string();
  });
}

Result<ChildRun> Lookups(const fs::path& db, const LookupSettings& settings) {
  spdlog::info("bench mosaic: timing lookups in {}", db.string());
  return RunInChild([&]() -> Result<std::string> {
    Result<LookupTimes> times = MeasureLookups(db.string(), settings);
    if (!times.ok()) return times.status();
    return LookupTimesJson(*times).dump();
  });
}

}  // namespace

Result<MosaicSizeBench> BenchMosaicSize(cv::Size size_px, const MosaicBenchSettings& settings) {
  const fs::path dir = settings.work_dir / SizeName(size_px);
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) return Internal(dir.string() + ": cannot create: " + ec.message());
  const fs::path pgm = dir / "floor.pgm", db = dir / "mosaic.db";
  RemoveMosaicFiles(db);  // ImportImage refuses to overwrite
  MosaicSizeBench bench;
  bench.size_px = size_px;
  Result<ChildRun> compose = Compose(size_px, settings, pgm);
  if (!compose.ok()) return compose.status();
  bench.compose = *compose;
  bench.caller_rss_bytes = ResidentBytes();
  Result<ChildRun> import = Import(pgm, settings.resolution_m, db);
  if (!import.ok()) return import.status();
  bench.import = *import;
  Result<ChildRun> lookup = Lookups(db, settings.lookups);
  if (!lookup.ok()) return lookup.status();
  bench.lookup = *lookup;
  Result<LookupTimes> times =
      LookupTimesFromJson(nlohmann::json::parse(lookup->output, nullptr, false));
  if (!times.ok()) return times.status();
  bench.times = *times;
  bench.pgm_bytes = fs::file_size(pgm, ec);
  bench.mosaic_bytes = fs::file_size(db, ec);
  if (!settings.keep_files) {
    fs::remove(pgm, ec);
    RemoveMosaicFiles(db);
  }
  return bench;
}

}  // namespace fleetloc::fleetctl
