// fleetctl bench tracker: fleetloc's tracker against the OpenCV peers on simulated runs over real
// floor mosaics, all on one core. Progress on stderr; one table per floor, an overall table and the
// verdicts on stdout; every number as JSON with --json.
#include "harness/tracker/run_tracker_bench.h"

#include <spdlog/spdlog.h>
#include <sys/resource.h>

#include <algorithm>
#include <iostream>
#include <nlohmann/json.hpp>
#include <opencv2/core/utility.hpp>
#include <set>

#include "harness/tracker/bench_report.h"
#include "io/file_util.h"
#include "support/floor_images.h"

namespace fleetloc::bench {
namespace {

namespace fs = std::filesystem;

Result<std::vector<fs::path>> ResolveFloors(const TrackerBenchArgs& args) {
  if (args.floors.empty()) {
    return fleetctl::ListFloorImages(
        args.floors_dir.empty() ? fleetctl::DefaultFloorsDir() : fs::path(args.floors_dir),
        "--floors-dir");
  }
  std::vector<fs::path> floors;
  for (const std::string& floor : args.floors) {
    std::error_code ec;
    if (!fs::is_regular_file(floor, ec)) return NotFound(floor + ": not found (--floors)");
    floors.emplace_back(floor);
  }
  return floors;
}

// Each method known and named once. InvalidInput naming the offending one.
Status ValidateMethods(const std::vector<std::string>& methods) {
  const std::vector<std::string> known = BenchMethodNames();
  if (methods.empty()) return InvalidInput("--methods: name at least one method");
  std::set<std::string> seen;
  for (const std::string& m : methods) {
    if (std::find(known.begin(), known.end(), m) == known.end()) {
      return InvalidInput("--methods: unknown method '" + m +
                          "' (known: fleetloc,orb,sift,ecc,phase)");
    }
    if (!seen.insert(m).second) return InvalidInput("--methods: '" + m + "' named twice");
  }
  return Status::Ok();
}

nlohmann::json FloorJson(const FloorBench& floor, const std::vector<BenchRow>& rows,
                         const Verdict& verdict) {
  return {{"floor", floor.name},
          {"image", floor.image.string()},
          {"mosaic", floor.mosaic.string()},
          {"run", floor.run_dir.string()},
          {"mosaic_px", {floor.width_px, floor.height_px}},
          {"frames", floor.frames},
          {"peer_frames", floor.peer_frames},
          {"sim",
           {{"distance_m", floor.sim.distance_m},
            {"laps", floor.sim.laps},
            {"overlapping_pairs_fraction", floor.sim.overlapping_pairs_fraction},
            {"floor_fraction_seen", floor.sim.floor_fraction_seen},
            {"odometry_drift_m", floor.sim.odometry_drift_m}}},
          {"methods", RowsJson(rows)},
          {"verdict", VerdictJson(verdict)},
          {"tile_cache_bytes", floor.tile_cache_bytes}};
}

// Prints one floor's header, table and verdict; returns its JSON.
nlohmann::json ReportFloor(const FloorBench& floor, const BenchSettings& settings) {
  const std::vector<BenchRow> rows = ScoreRows(TableReplays(floor));
  const Verdict verdict = Judge(rows);
  std::cout << "\n== floor " << floor.name << ": " << floor.width_px << "x" << floor.height_px
            << " px mosaic at " << settings.resolution_m << " m/px; " << floor.frames
            << " frames at " << settings.rate_hz << " Hz, " << settings.speed_px_s << " px/s, seed "
            << settings.seed << "; run " << floor.run_dir.string() << "\n";
  if (floor.peer_frames < floor.frames) {
    std::cout << "peers ran on the first " << floor.peer_frames << " of " << floor.frames
              << " frames (--peer-frames); fleetloc@" << floor.peer_frames
              << " is fleetloc on those frames\n";
  }
  PrintTable(std::cout, "", rows);
  PrintVerdict(std::cout, floor.name, verdict);
  std::cout << "tile cache at the end: " << floor.tile_cache_bytes << " bytes\n" << std::flush;
  return FloorJson(floor, rows, verdict);
}

nlohmann::json SettingsJson(const BenchSettings& s) {
  return {{"resolution_m", s.resolution_m},
          {"frames", s.frames},
          {"rate_hz", s.rate_hz},
          {"speed_px_s", s.speed_px_s},
          {"seed", s.seed},
          {"methods", s.methods},
          {"peer_frames", s.peer_frames},
          {"work_dir", s.work_dir.string()},
          {"threads", 1}};
}

long long PeakRssBytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<long long>(usage.ru_maxrss) * 1024;  // Linux reports KiB
}

}  // namespace

Status RunTrackerBench(TrackerBenchArgs args) {
  FLEETLOC_RETURN_IF_ERROR(ValidateMethods(args.settings.methods));
  FLEETLOC_RETURN_IF_ERROR(LoadBenchTrackerOptions(args.tracker_config, &args.settings));
  Result<std::vector<fs::path>> floors = ResolveFloors(args);
  if (!floors.ok()) return floors.status();
  args.settings.work_dir = io::AbsoluteDir(args.work_dir);
  cv::setNumThreads(1);  // every method on one core
  nlohmann::json json{{"settings", SettingsJson(args.settings)},
                      {"floors", nlohmann::json::array()}};
  std::vector<FloorBench> benches;
  for (const fs::path& image : *floors) {
    Result<FloorBench> bench = BenchFloor(image, args.settings);
    if (!bench.ok()) return bench.status();
    json["floors"].push_back(ReportFloor(*bench, args.settings));
    benches.push_back(std::move(*bench));
  }
  const std::vector<BenchRow> overall = ScoreRows(OverallReplays(benches));
  const Verdict verdict = Judge(overall);
  PrintTable(std::cout,
             "\n== overall: " + std::to_string(benches.size()) +
                 (benches.size() == 1 ? " floor" : " floors") + ", every table row concatenated",
             overall);
  PrintVerdict(std::cout, "overall", verdict);
  const long long rss = PeakRssBytes();
  std::cout << "peak RSS: " << rss / (1 << 20) << " MiB\n";
  json["overall"] = {{"methods", RowsJson(overall)}, {"verdict", VerdictJson(verdict)}};
  json["peak_rss_bytes"] = rss;
  if (args.json.empty()) return Status::Ok();
  return io::WriteFileAtomically(args.json, json.dump(2) + "\n");
}

}  // namespace fleetloc::bench
