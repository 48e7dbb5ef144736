// fleetctl bench remap: a re-mapping job over many stored patches (default 1,000 views of the demo
// floor from 10 vehicles, each off its true pose by up to 2 px), run in a forked child so its peak
// resident memory is its own: the job streams the patches (one decoded image at a time, plus the
// tiles it writes), and for comparison a child that only reads every patch of the region into
// memory, as jobs did before issue 18. No assertions: numbers for docs/benchmarks.md.
#include "harness/map_server/bench_remap.h"

#include <spdlog/spdlog.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/core/utility.hpp>
#include <random>

#include "harness/common/bench_paths.h"
#include "harness/common/forked_step.h"
#include "mosaic_upkeep/remap_job.h"
#include "run_io/run.h"
#include "support/floor_images.h"

namespace fleetloc::bench {
namespace {

namespace fs = std::filesystem;

constexpr double kRes = 0.0005;

// A fresh copy of the demo mosaic with `n` patches stored: 320x240 crops of the floor at random
// places and headings, reported off by up to 2 px, from 10 vehicles.
Result<std::string> MosaicWithPatches(const RemapBenchArgs& a) {
  Result<std::string> demo =
      EnsureDemoMosaic(a.work_dir, "rock_dirt_2048.png", "remap_bench_demo.db");
  if (!demo.ok()) return demo.status();
  const std::string path = a.work_dir + "/remap_bench.db";
  fs::remove(path);
  fs::remove(path + "-wal");
  fs::remove(path + "-shm");
  fs::copy_file(*demo, path);
  Result<cv::Mat> floor =
      run_io::ReadGrayImage(fleetctl::DefaultFloorsDir() / "rock_dirt_2048.png");
  if (!floor.ok()) return floor.status();
  auto store = mosaic::PatchStore::Open(path);
  if (!store.ok()) return store.status();
  std::mt19937 rng(18);
  std::uniform_real_distribution<double> where(300, 1748), error(-2, 2);
  for (int i = 0; i < a.patches; ++i) {
    const double u = where(rng), v = where(rng);
    const cv::Rect crop(static_cast<int>(u) - 160, static_cast<int>(v) - 120, 320, 240);
    mosaic::PatchRecord p;
    p.vehicle_id = "v" + std::to_string(i % 10);
    p.sequence = i + 1;
    p.stamp_s = i;
    // The crop's centre in map (docs/formats.md: y up), the camera looking along the image's up.
    const double cx = crop.x + 160.0, cy = crop.y + 120.0;
    p.pose = {cx * kRes + error(rng) * kRes, (2048 - cy) * kRes + error(rng) * kRes, M_PI / 2};
    p.covariance = Eigen::Vector3d(std::pow(3 * kRes, 2), std::pow(3 * kRes, 2), 1e-4).asDiagonal();
    p.quality = 0.9;
    p.image = (*floor)(crop).clone();
    Result<mosaic::PutOutcome> put = (*store)->Put(p);
    if (!put.ok()) return put.status();
  }
  return path;
}

nlohmann::json Usage(const ChildRun& run) {
  return {{"wall_s", run.wall_s},
          {"cpu_s", run.user_s + run.system_s},
          {"peak_rss_mb", static_cast<double>(run.peak_rss_bytes) / (1 << 20)}};
}

}  // namespace

Status RunRemapBench(const RemapBenchArgs& a) {
  cv::setNumThreads(1);  // one core; and no worker threads may exist when the steps fork
  fs::create_directories(a.work_dir);
  spdlog::info("bench remap: storing {} patches", a.patches);
  // In a child too, so the caller stays small for the measured children.
  Result<ChildRun> setup = RunInChild([&] { return MosaicWithPatches(a); });
  if (!setup.ok()) return setup.status();
  const Result<std::string> path = setup->output;
  const mosaic::MapRect everywhere{0, 0, 2048 * kRes, 2048 * kRes};
  const long long parent_rss = ResidentBytes();
  spdlog::info("bench remap: every patch read into memory (as before)");
  Result<ChildRun> held = RunInChild([&]() -> Result<std::string> {
    auto store = mosaic::PatchStore::Open(*path);
    if (!store.ok()) return store.status();
    Result<mosaic::PatchQuery> all = (*store)->Unfolded(everywhere, 1);
    if (!all.ok()) return all.status();
    return std::to_string(all->patches.size());
  });
  if (!held.ok()) return held.status();
  spdlog::info("bench remap: the streaming re-mapping job");
  Result<ChildRun> job = RunInChild([&]() -> Result<std::string> {
    auto tiles = mosaic::TileStore::Open(*path, mosaic::OpenMode::kReadWrite);
    auto patches = mosaic::PatchStore::Open(*path);
    auto standing = mosaic_upkeep::VehicleStandingStore::Open(*path);
    if (!tiles.ok() || !patches.ok() || !standing.ok()) return Internal("cannot open " + *path);
    Result<mosaic_upkeep::RemapResult> r = mosaic_upkeep::RunRemap(
        **tiles, **patches, **standing, {everywhere, mosaic_upkeep::RemapMode::kBlend});
    if (!r.ok()) return r.status();
    return nlohmann::json{{"folded", r->patches_folded},
                          {"refused", r->patches_rejected},
                          {"tiles_changed", r->changed_tiles.size()},
                          {"new_version", r->new_version}}
        .dump();
  });
  if (!job.ok()) return job.status();
  const nlohmann::json outcome = nlohmann::json::parse(job->output);
  const nlohmann::json out = {
      {"patches", a.patches},
      {"parent_rss_mb_at_fork", static_cast<double>(parent_rss) / (1 << 20)},
      {"read_all_into_memory", Usage(*held)},
      {"streaming_job", Usage(*job)},
      {"job", outcome}};
  std::printf("re-mapping job over %d patches (320x240, 10 vehicles), demo floor 2048x2048\n",
              a.patches);
  std::printf("  job: %d folded, %d refused, %zu tiles changed, %.1f s, peak RSS %.1f MB\n",
              outcome["folded"].get<int>(), outcome["refused"].get<int>(),
              outcome["tiles_changed"].get<size_t>(), job->wall_s,
              static_cast<double>(job->peak_rss_bytes) / (1 << 20));
  std::printf(
      "  only reading every patch into memory (as jobs did before): %.1f s, peak RSS %.1f MB\n",
      held->wall_s, static_cast<double>(held->peak_rss_bytes) / (1 << 20));
  std::printf("  (both include the caller's %.1f MB resident at the fork)\n",
              static_cast<double>(parent_rss) / (1 << 20));
  if (!a.json.empty()) std::ofstream(a.json) << out.dump(2) << "\n";
  return Status::Ok();
}

}  // namespace fleetloc::bench
