// Per-floor tracker benchmark: mosaic import (reused while the image is unchanged), simulated run
// written and read back, every method replayed over one warm tile cache.
#include "harness/tracker/bench_tracker.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <nlohmann/json.hpp>

#include "io/file_util.h"
#include "mosaic/importer.h"
#include "mosaic/tile_store.h"
#include "peers/make_peer.h"
#include "run_io/tracker_config.h"
#include "support/sim_run_writer.h"
#include "tracking/mosaic_tracker.h"

namespace fleetloc::bench {
namespace {

namespace fs = std::filesystem;

constexpr int kSimProgressEvery = 200;     // frames between progress lines
constexpr int kReplayProgressEvery = 500;  // frames between progress lines
constexpr std::size_t kMinTileCacheBytes = 64 << 20;

// What the mosaic in a floor's work directory was made from; a mosaic is reused only when the
// stamp stored beside it equals the image's current one.
Result<nlohmann::json> SourceStamp(const fs::path& image, double resolution_m) {
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(image, ec);
  if (ec) return NotFound(image.string() + ": not found");
  const fs::file_time_type mtime = fs::last_write_time(image, ec);
  if (ec) return Internal(image.string() + ": cannot stat: " + ec.message());
  return nlohmann::json{{"image", fs::absolute(image).lexically_normal().string()},
                        {"size_bytes", size},
                        {"mtime_ticks", mtime.time_since_epoch().count()},
                        {"resolution_m", resolution_m}};
}

bool StampMatches(const fs::path& stamp_file, const nlohmann::json& stamp) {
  Result<std::string> text = io::ReadFileText(stamp_file);
  if (!text.ok()) return false;
  const nlohmann::json stored = nlohmann::json::parse(*text, nullptr, /*allow_exceptions=*/false);
  return stored == stamp;
}

Status ImportFresh(const fs::path& image, double resolution_m, const fs::path& db) {
  std::error_code ec;
  for (const char* suffix : {"", "-wal", "-shm", ".partial"}) fs::remove(db.string() + suffix, ec);
  mosaic::ImportOptions options;
  options.resolution_m = resolution_m;
  spdlog::info("bench: importing {} into {}", image.string(), db.string());
  Result<mosaic::MosaicLayout> layout = mosaic::ImportImage(image.string(), options, db.string());
  return layout.status();
}

}  // namespace

Result<std::shared_ptr<mosaic::TileStore>> OpenFloorMosaic(const fs::path& image,
                                                           double resolution_m,
                                                           const fs::path& floor_dir) {
  Result<nlohmann::json> stamp = SourceStamp(image, resolution_m);
  if (!stamp.ok()) return stamp.status();
  const fs::path db = floor_dir / "mosaic.db";
  const fs::path stamp_file = floor_dir / "mosaic.source.json";
  if (StampMatches(stamp_file, *stamp)) {
    Result<std::unique_ptr<mosaic::TileStore>> reused =
        mosaic::TileStore::Open(db.string(), mosaic::OpenMode::kReadOnly);
    if (reused.ok()) {
      spdlog::info("bench: reusing {}", db.string());
      return std::shared_ptr<mosaic::TileStore>(std::move(*reused));
    }
  }
  std::error_code ec;
  fs::create_directories(floor_dir, ec);
  if (ec) return Internal(floor_dir.string() + ": cannot create: " + ec.message());
  FLEETLOC_RETURN_IF_ERROR(ImportFresh(image, resolution_m, db));
  FLEETLOC_RETURN_IF_ERROR(io::WriteFileAtomically(stamp_file, stamp->dump(2) + "\n"));
  Result<std::unique_ptr<mosaic::TileStore>> opened =
      mosaic::TileStore::Open(db.string(), mosaic::OpenMode::kReadOnly);
  if (!opened.ok()) return opened.status();
  return std::shared_ptr<mosaic::TileStore>(std::move(*opened));
}

namespace {

sim::SimOptions SimOptionsFor(const BenchSettings& settings) {
  sim::SimOptions options;  // the realistic defaults of `fleetctl sim`
  options.timing.frames = settings.frames;
  options.timing.frame_rate_hz = settings.rate_hz;
  options.route.speed_px_s = settings.speed_px_s;
  options.route.shape = settings.route;
  options.seed = settings.seed;
  options.render = settings.render;
  return options;
}

// Writes the simulated run into run_dir with `fleetctl sim`'s code and reads it back.
Result<run_io::Run> SimulateRun(mosaic::RasterSource* floor, const BenchSettings& settings,
                                const fs::path& run_dir, sim::SimSummary* summary) {
  const sim::SimOptions options = SimOptionsFor(settings);
  FLEETLOC_RETURN_IF_ERROR(sim::Validate(options));
  const run_io::CameraFile camera = fleetctl::DefaultSimCamera(
      settings.width_px, settings.height_px, floor->layout().geo.resolution);
  Result<std::unique_ptr<sim::RunSimulator>> simulator =
      sim::RunSimulator::Create(floor, camera.model, options);
  if (!simulator.ok()) return simulator.status();
  FLEETLOC_RETURN_IF_ERROR(fleetctl::PrepareRunDir(run_dir, /*overwrite=*/true));
  const auto progress = [&run_dir](int done, int total) {
    if (done % kSimProgressEvery == 0 || done == total) {
      spdlog::info("bench: sim {} {}/{} frames", run_dir.string(), done, total);
    }
  };
  Result<run_io::Run> written =
      fleetctl::WriteSimulatedRun(**simulator, camera, run_dir, "bench", progress);
  if (!written.ok()) return written.status();
  *summary = (*simulator)->summary();
  return run_io::ReadRun(run_dir);
}

// "rock_dirt_2048.png" → "rock_dirt_2048_png": one work directory per image file.
std::string FloorDirName(const fs::path& image) {
  std::string name = image.filename().string();
  std::replace(name.begin(), name.end(), '.', '_');
  return name;
}

std::size_t PyramidBytes(const mosaic::MosaicLayout& layout) {
  std::size_t tiles = 0;
  for (int level = 0; level < layout.levels; ++level) {
    tiles += static_cast<std::size_t>(mosaic::TileColumns(layout, level)) *
             mosaic::TileRows(layout, level);
  }
  return tiles * layout.tile_size_px * layout.tile_size_px;
}

// Reads every tile of every level once, so no method pays for SQLite reads or PNG decoding.
void WarmTileCache(mosaic::MosaicView& view) {
  const mosaic::MosaicLayout& layout = view.layout();
  for (int level = 0; level < layout.levels; ++level) {
    for (int row = 0; row < mosaic::TileRows(layout, level); ++row) {
      for (int col = 0; col < mosaic::TileColumns(layout, level); ++col) {
        view.ReadBlock(level, mosaic::TilePixelRect(layout, {level, col, row}));
      }
    }
  }
}

std::unique_ptr<tracking::FrameLocalizer> MakeLocalizer(const std::string& method,
                                                        const geometry::CameraModel& camera,
                                                        mosaic::RasterSource* view,
                                                        const tracking::TrackerOptions& options) {
  if (method == "fleetloc") {
    return std::make_unique<tracking::MosaicTracker>(options, camera, view);
  }
  return peers::MakePeer(method, camera, view);
}

Result<MethodReplay> ReplayMethod(const std::string& method, run_io::Run run,
                                  mosaic::RasterSource* view,
                                  const tracking::TrackerOptions& options) {
  std::unique_ptr<tracking::FrameLocalizer> localizer =
      MakeLocalizer(method, run.camera.model, view, options);
  if (!localizer) return InvalidInput("--methods: unknown method '" + method + "'");
  const auto progress = [&method](size_t done, size_t total) {
    if (done % kReplayProgressEvery == 0 || done == total) {
      spdlog::info("bench: {} {}/{} frames", method, done, total);
    }
  };
  Result<replay::ReplayResult> replayed = replay::ReplayRun(run, *localizer, progress);
  if (!replayed.ok()) return replayed.status();
  return MethodReplay{method, std::move(run), std::move(*replayed)};
}

// fleetloc's replay of `run` `replays` times (each with a new tracker), each frame's time the
// least of its replays (TakeLeastTimes).
Result<MethodReplay> ReplayFleetlocTimed(const run_io::Run& run, mosaic::RasterSource* view,
                                         const tracking::TrackerOptions& options, int replays) {
  Result<MethodReplay> first = ReplayMethod("fleetloc", run, view, options);
  if (!first.ok()) return first.status();
  for (int r = 1; r < replays; ++r) {
    Result<MethodReplay> again = ReplayMethod("fleetloc", run, view, options);
    if (!again.ok()) return again.status();
    FLEETLOC_RETURN_IF_ERROR(TakeLeastTimes(again->replayed, &first->replayed));
  }
  return first;
}

}  // namespace

Status TakeLeastTimes(const replay::ReplayResult& again, replay::ReplayResult* first) {
  const auto same = [](double u, double v) { return u == v || (std::isnan(u) && std::isnan(v)); };
  const auto same_pose = [&same](const run_io::PoseRecord& p, const run_io::PoseRecord& q) {
    return p.status == q.status && same(p.pose.x, q.pose.x) && same(p.pose.y, q.pose.y) &&
           same(p.pose.theta, q.pose.theta);
  };
  if (!std::equal(first->poses.begin(), first->poses.end(), again.poses.begin(), again.poses.end(),
                  same_pose) ||
      first->cycle_ms.size() != again.cycle_ms.size()) {
    return Internal(
        "bench: a replay of fleetloc gave other poses than the first: the tracker is "
        "not deterministic, so its replays' times are not of the same work");
  }
  for (size_t i = 0; i < again.cycle_ms.size(); ++i) {
    first->cycle_ms[i] = std::min(first->cycle_ms[i], again.cycle_ms[i]);
  }
  return Status::Ok();
}

Status LoadBenchTrackerOptions(const std::string& path, BenchSettings* settings) {
  if (path.empty()) return Status::Ok();
  Result<tracking::TrackerOptions> options = run_io::ReadTrackerOptions(path);
  if (!options.ok()) return options.status();
  settings->tracker = *options;
  return Status::Ok();
}

std::vector<std::string> BenchMethodNames() {
  std::vector<std::string> names{"fleetloc"};
  for (const std::string& peer : peers::PeerNames()) names.push_back(peer);
  return names;
}

run_io::Run FirstFrames(const run_io::Run& run, std::size_t count) {
  run_io::Run first = run;
  first.frames.resize(std::min(count, run.frames.size()));
  first.truth.resize(std::min(count, run.truth.size()));
  return first;
}

Result<FloorBench> BenchFloor(const fs::path& image, const BenchSettings& settings) {
  FloorBench bench;
  bench.name = image.filename().string();
  bench.image = image;
  const fs::path floor_dir = settings.work_dir / FloorDirName(image);
  Result<std::shared_ptr<mosaic::TileStore>> store =
      OpenFloorMosaic(image, settings.resolution_m, floor_dir);
  if (!store.ok()) return store.status();
  const mosaic::MosaicLayout layout = (*store)->layout();
  bench.mosaic = (*store)->path();
  bench.width_px = layout.width_px;
  bench.height_px = layout.height_px;
  mosaic::MosaicView view(
      layout, mosaic::MakeTileLoader(*store),
      std::make_shared<mosaic::TileCache>(std::max(kMinTileCacheBytes, PyramidBytes(layout) * 2)));
  bench.run_dir = floor_dir / "run";
  Result<run_io::Run> run = SimulateRun(&view, settings, bench.run_dir, &bench.sim);
  if (!run.ok()) return run.status();
  bench.frames = static_cast<int>(run->frames.size());
  bench.peer_frames =
      settings.peer_frames > 0 ? std::min(settings.peer_frames, bench.frames) : bench.frames;
  WarmTileCache(view);
  for (const std::string& method : settings.methods) {
    const bool peer = method != "fleetloc";
    Result<MethodReplay> replayed =
        peer ? ReplayMethod(method, FirstFrames(*run, bench.peer_frames), &view, settings.tracker)
             : ReplayFleetlocTimed(*run, &view, settings.tracker,
                                   std::max(1, settings.timing_replays));
    if (!replayed.ok()) return replayed.status();
    bench.methods.push_back(std::move(*replayed));
  }
  bench.tile_cache_bytes = view.cache().stats().bytes;
  return bench;
}

}  // namespace fleetloc::bench
