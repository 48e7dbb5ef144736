// fleetctl bench reloc: global relocalization at scale (issue 5). On a non-repeating real-texture
// floor mosaic of >= 100 megapixels (composed from the demo photos with every block randomly
// rotated and scaled, imported at 0.5 mm/px — or --mosaic), build the place index in a child
// process (time, size, peak RSS), load it as the agent would (from the mosaic's cache table), and
// relocalize sim-rendered frames from random poses: success rate, time to the first correct pose,
// wrong poses. Progress on stderr; the summary on stdout; every number as JSON with --json.
#include "harness/reloc/run_reloc_bench.h"

#include <spdlog/spdlog.h>

#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <opencv2/core/utility.hpp>

#include "harness/common/forked_step.h"
#include "harness/reloc/bench_reloc.h"
#include "harness/reloc/bench_reloc_stress.h"
#include "io/file_util.h"
#include "mosaic/importer.h"
#include "mosaic_upkeep/place_index_cache.h"
#include "support/composed_floor.h"
#include "support/floor_images.h"
#include "support/reloc_index.h"

namespace fleetloc::bench {
namespace {

namespace fs = std::filesystem;

mosaic::ImportOptions ImportAtHalfMillimetre() {
  mosaic::ImportOptions options;
  options.resolution_m = 0.0005;
  return options;
}

// The composed, imported mosaic of args.size (kept in the work dir and reused when present).
Result<std::string> PrepareMosaic(const RelocBenchArgs& args) {
  if (!args.mosaic.empty()) return args.mosaic;
  Result<cv::Size> size = fleetctl::ParsePixelSize(args.size, "--size");
  if (!size.ok()) return size.status();
  const fs::path dir = io::AbsoluteDir(args.work_dir);
  const std::string stem = "floor_" + args.size + "_seed" + std::to_string(args.trials.seed);
  const std::string db = (dir / (stem + ".db")).string();
  if (fs::exists(db)) return db;
  Result<std::vector<fs::path>> photos = fleetctl::ListFloorImages(
      args.floors_dir.empty() ? fleetctl::DefaultFloorsDir() : fs::path(args.floors_dir),
      "--floors-dir");
  if (!photos.ok()) return photos.status();
  sim::FloorComposerOptions compose{.width_px = size->width, .height_px = size->height};
  compose.seed = args.trials.seed;
  compose.free_rotation_and_scale = true;
  const std::string pgm = (dir / (stem + ".pgm")).string();
  std::vector<std::string> names;
  for (const fs::path& p : *photos) names.push_back(p.string());
  FLEETLOC_RETURN_IF_ERROR(fleetctl::ComposeFloorPgm(names, compose, pgm));
  Result<mosaic::MosaicLayout> imported = mosaic::ImportImage(pgm, ImportAtHalfMillimetre(), db);
  fs::remove(pgm);
  if (!imported.ok()) return imported.status();
  return db;
}

Result<std::shared_ptr<mosaic::TileStore>> OpenStore(const std::string& path) {
  Result<std::unique_ptr<mosaic::TileStore>> opened =
      mosaic::TileStore::Open(path, mosaic::OpenMode::kReadOnly);
  if (!opened.ok()) return opened.status();
  return std::shared_ptr<mosaic::TileStore>(std::move(opened).value());
}

// Builds the index in a child process (so its peak RSS is its own) and stores it in the mosaic.
Result<ChildRun> BuildIndexInChild(const std::string& db,
                                   const relocalization::PlaceIndexOptions& o) {
  return RunInChild([&]() -> Result<std::string> {
    Result<std::shared_ptr<mosaic::TileStore>> store = OpenStore(db);
    if (!store.ok()) return store.status();
    mosaic::MosaicView view((*store)->layout(), mosaic::MakeTileLoader(*store),
                            std::make_shared<mosaic::TileCache>(64LL << 20));
    Result<mosaic_upkeep::LoadedPlaceIndex> built =
        mosaic_upkeep::LoadOrBuildPlaceIndex(db, view, o, mosaic_upkeep::IndexCache::kRebuild);
    if (!built.ok()) return built.status();
    return nlohmann::json{{"features", built->index.size()},
                          {"blob_bytes", built->blob.size()},
                          {"seconds", built->seconds}}
        .dump();
  });
}

void PrintSummary(const nlohmann::json& j) {
  const auto& st = j["trials"];
  std::cout << "\n== global relocalization: " << j["mosaic"]["megapixels"].get<double>()
            << " Mpx mosaic " << j["mosaic"]["path"].get<std::string>() << "\n"
            << "index: " << j["index"]["features"] << " features, " << j["index"]["blob_bytes"]
            << " bytes, built in " << j["index"]["build_s"] << " s (peak RSS "
            << j["index"]["build_peak_rss_bytes"] << " B), loaded in " << j["index"]["load_s"]
            << " s\n"
            << "trials " << st["trials"] << ": correct " << st["correct"] << " ("
            << st["success_rate"] << "), within 1 s " << st["correct_within_target"] << " ("
            << st["success_rate_within_target"] << "), wrong " << st["wrong_pose"] << ", not found "
            << st["not_found"] << "\n"
            << "time to correct pose ms " << st["time_to_correct_pose_ms"].dump()
            << "; per attempt ms " << st["attempt_ms"].dump() << "; stages p50 "
            << st["stage_ms_p50"].dump() << "\n"
            << "RSS after trials " << j["rss_after_trials_bytes"] << " B\n";
}

}  // namespace

Status RunRelocBench(const RelocBenchArgs& args) {
  cv::setNumThreads(1);  // one core; and no worker threads may exist when the build forks
  FLEETLOC_RETURN_IF_ERROR(relocalization::Validate(args.index));
  FLEETLOC_RETURN_IF_ERROR(relocalization::Validate(args.trials.relocalizer));
  if (args.stress) {
    RelocStressArgs stressed = args.stressed;
    stressed.index = args.index;
    stressed.trials = args.trials;
    stressed.json = args.json;
    stressed.work_dir = args.work_dir;
    return RunRelocStress(stressed);
  }
  Result<std::string> db = PrepareMosaic(args);
  if (!db.ok()) return db.status();
  Result<ChildRun> build = BuildIndexInChild(*db, args.index);
  if (!build.ok()) return build.status();
  const nlohmann::json built = nlohmann::json::parse(build->output);
  Result<std::shared_ptr<mosaic::TileStore>> store = OpenStore(*db);
  if (!store.ok()) return store.status();
  mosaic::MosaicView view((*store)->layout(), mosaic::MakeTileLoader(*store),
                          std::make_shared<mosaic::TileCache>(64LL << 20));
  Result<mosaic_upkeep::LoadedPlaceIndex> index =
      mosaic_upkeep::LoadOrBuildPlaceIndex(*db, view, args.index, mosaic_upkeep::IndexCache::kUse);
  if (!index.ok()) return index.status();
  Result<std::vector<RelocTrial>> trials = RunRelocTrials(*store, &index->index, args.trials);
  if (!trials.ok()) return trials.status();
  const mosaic::MosaicLayout layout = (*store)->layout();
  nlohmann::json json{
      {"mosaic",
       {{"path", *db},
        {"width_px", layout.width_px},
        {"height_px", layout.height_px},
        {"megapixels", layout.width_px * static_cast<double>(layout.height_px) / 1e6}}},
      {"index",
       {{"key", mosaic_upkeep::PlaceIndexKey(args.index)},
        {"features", built["features"]},
        {"blob_bytes", built["blob_bytes"]},
        {"build_s", built["seconds"]},
        {"build_peak_rss_bytes", build->peak_rss_bytes},
        {"load_s", index->seconds},
        {"from_cache", index->from_cache}}},
      {"settings",
       {{"seed", args.trials.seed},
        {"attempts", args.trials.attempts},
        {"frame_period_s", args.trials.frame_period_s},
        {"max_error_m", args.trials.max_error_m},
        {"max_error_rad", args.trials.max_error_rad},
        {"tile_cache_bytes_per_trial", args.trials.tile_cache_bytes}}},
      {"trials", RelocTrialStats(*trials, args.trials)},
      {"rss_after_trials_bytes", ResidentBytes()}};
  PrintSummary(json);
  if (args.json.empty()) return Status::Ok();
  return io::WriteFileAtomically(args.json, json.dump(2) + "\n");
}

}  // namespace fleetloc::bench
