// fleetctl bench tracker: fleetloc's tracker against the OpenCV peers on simulated runs over real
// floor mosaics, all on one core. Progress on stderr; one table per floor, an overall table and the
// verdicts on stdout; every number as JSON with --json.
#include <spdlog/spdlog.h>
#include <sys/resource.h>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <opencv2/core/utility.hpp>
#include <set>
#include <string>
#include <vector>

#include "bench_mosaic_build.h"
#include "bench_mosaic_distortion.h"
#include "bench_paths.h"
#include "bench_report.h"
#include "bench_agent.h"
#include "bench_agent_live.h"
#include "bench_mapfit.h"
#include "bench_tiles.h"
#include "bench_tracker.h"
#include "commands.h"
#include "floor_images.h"
#include "io/file_util.h"

namespace fleetloc::fleetctl {
namespace {

namespace fs = std::filesystem;

struct BenchArgs {
  std::vector<std::string> floors;
  std::string floors_dir;
  std::string work_dir = (fs::temp_directory_path() / "fleetloc-bench").string();
  std::string json;
  std::string tracker_config;
  BenchSettings settings;
};

Result<std::vector<fs::path>> ResolveFloors(const BenchArgs& args) {
  if (args.floors.empty()) {
    return ListFloorImages(args.floors_dir.empty() ? DefaultFloorsDir() : fs::path(args.floors_dir),
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

Status RunBench(BenchArgs& args) {
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

void AddBenchTrackerOptions(CLI::App* tracker, BenchArgs* a) {
  BenchSettings& s = a->settings;
  s.methods = BenchMethodNames();
  tracker
      ->add_option("--floors", a->floors,
                   "Floor images, comma-separated (default: every image "
                   "in --floors-dir)")
      ->delimiter(',');
  tracker->add_option(
      "--floors-dir", a->floors_dir,
      "Directory of floor images (default: the source tree's " + std::string(kFloorsSubdir) + ")");
  tracker->add_option("--resolution", s.resolution_m, "Metres per pixel of the floor images");
  tracker->add_option("--frames", s.frames, "Frames per run")->check(CLI::Range(1, 1000000));
  tracker->add_option("--rate-hz", s.rate_hz, "Frame rate");
  tracker->add_option("--speed-px-s", s.speed_px_s, "Footprint speed, floor pixels per second");
  tracker->add_option("--methods", s.methods, "fleetloc and peers (orb, sift, ecc, phase)")
      ->delimiter(',');
  tracker->add_option("--work-dir", a->work_dir, "Mosaics (reused) and simulated runs");
  tracker->add_option("--seed", s.seed, "Simulation seed");
  tracker->add_option("--json", a->json, "Write every number to this JSON file");
  tracker->add_option("--tracker-config", a->tracker_config,
                      "fleetloc's tracker options (JSON, as fleetctl track --config)");
  tracker
      ->add_option("--peer-frames", s.peer_frames,
                   "Peers replay only the first N frames (0: all; SIFT is slow)")
      ->check(CLI::Range(0, 1000000));
}

void RegisterBenchTiles(CLI::App* bench, Status* result) {
  auto s = std::make_shared<TileBenchSettings>();
  s->work_dir = (fs::temp_directory_path() / "fleetloc-bench-tiles").string();
  CLI::App* tiles = bench->add_subcommand(
      "tiles", "Tile streaming from a map_server process: throughput and latency vs ddsperf");
  tiles->option_defaults()->always_capture_default();
  tiles->add_option("--mosaic", s->mosaic, "Mosaic to serve (default: import the demo rock floor)");
  tiles->add_option("--work-dir", s->work_dir, "Logs, configuration and the imported mosaic");
  tiles->add_option("--domain", s->domain, "DDS domain (ddsperf uses the next one)")
      ->check(CLI::Range(0, 231));
  tiles->add_option("--seconds", s->seconds, "Duration of each phase")->check(CLI::Range(1.0, 600.0));
  tiles->add_option("--vehicles", s->vehicles, "Vehicle counts of the latency phases")
      ->delimiter(',')
      ->check(CLI::Range(1, 500));
  tiles->add_option("--rate-hz", s->rate_hz, "Tile requests per vehicle per second")
      ->check(CLI::Range(0.1, 1000.0));
  tiles->add_option("--batch", s->batch_tiles, "Tiles per request (throughput)")
      ->check(CLI::Range(1, 256));
  tiles->add_option("--pipeline", s->pipeline, "Requests in flight (throughput)")
      ->check(CLI::Range(1, 64));
  tiles->add_option("--json", s->json, "Write every number to this JSON file");
  tiles->add_option("--server-dds-config", s->server_dds_config,
                    "Cyclone DDS XML of the map server (default: built-in loopback)");
  tiles->add_option("--client-dds-config", s->client_dds_config,
                    "Cyclone DDS XML of the requesting participant (default: built-in loopback)");
  tiles->add_option("--peer-dds-config", s->peer_dds_config,
                    "Cyclone DDS XML of the ddsperf peer (default: built-in loopback)");
  tiles->callback([s, result] { *result = RunTileBench(*s); });
}

void RegisterBenchAgent(CLI::App* bench, Status* result) {
  auto s = std::make_shared<AgentBenchSettings>();
  s->work_dir = (fs::temp_directory_path() / "fleetloc-bench-agent").string();
  CLI::App* agent = bench->add_subcommand(
      "agent", "Tracker cycle on the live path (agent over DDS) vs the offline tracker, same run");
  agent->option_defaults()->always_capture_default();
  agent->add_option("--work-dir", s->work_dir, "Mosaic, run, logs");
  agent->add_option("--frames", s->frames, "Frames of the simulated run (--source aravis: 300 unless given)")
      ->check(CLI::Range(10, 100000));
  agent->add_option("--domain", s->domain, "DDS domain")->check(CLI::Range(0, 232));
  agent->add_option("--json", s->json, "Write every number to this JSON file");
  // --source aravis: a live vehicle (fake GigE Vision camera, ROS 2 odometry) instead of a replay.
  auto source = std::make_shared<std::string>("replay");
  auto rate = std::make_shared<double>(10.0);
  agent->add_option("--source", *source, "replay (cycle time, live vs offline), aravis or gstreamer (a live "
                                         "fake GigE Vision camera read by the Aravis source or by aravissrc: "
                                         "capture -> pose latency, live/offline accuracy)")
      ->check(CLI::IsMember({"replay", "aravis", "gstreamer"}));
  agent->add_option("--rate", *rate, "Camera frame rate, Hz (live sources)")->check(CLI::Range(1.0, 50.0));
  auto extrapolation = std::make_shared<double>(LiveAgentBenchSettings().odometry_extrapolation_s);
  agent->add_option("--odometry-extrapolation", *extrapolation,
                    "The agent's live.odometry_extrapolation_s (live sources; 0: frames wait for odometry)")
      ->check(CLI::Range(0.0, 0.1));
  auto gst_timestamps = std::make_shared<std::string>(LiveAgentBenchSettings().gstreamer_timestamps);
  agent->add_option("--gstreamer-timestamps", *gst_timestamps,
                    "--source gstreamer: device (aravissrc's PTS, the camera's clock) or created "
                    "(aravissrc do-timestamp=true)")
      ->check(CLI::IsMember({"device", "created"}));
  agent->callback([s, source, rate, extrapolation, gst_timestamps, result] {
    if (*source == "replay") return void(*result = RunAgentBench(*s));
    const bool frames_given = s->frames != AgentBenchSettings().frames;
    *result = RunLiveAgentBench({s->work_dir, frames_given ? s->frames : 300, *rate, s->domain, s->json,
                                 *source, *extrapolation, *gst_timestamps});
  });
}

}  // namespace

void RegisterBenchCommand(CLI::App& app, Status* result) {
  auto args = std::make_shared<BenchArgs>();
  CLI::App* bench = app.add_subcommand("bench", "Benchmarks");
  bench->require_subcommand(1);
  CLI::App* tracker = bench->add_subcommand(
      "tracker", "fleetloc's tracker against the OpenCV peers on simulated runs over real floors");
  tracker->option_defaults()->always_capture_default();
  AddBenchTrackerOptions(tracker, args.get());
  tracker->callback([args, result] { *result = RunBench(*args); });
  RegisterBenchTiles(bench, result);
  RegisterBenchAgent(bench, result);
  AddBenchMosaicCommand(*bench, result);
  RegisterBenchMosaicBuild(*bench, result);
  RegisterBenchMosaicDistortion(*bench, result);
  RegisterBenchMapFit(*bench, result);
  RegisterBenchReloc(*bench, result);
  RegisterBenchDenseProbe(*bench, result);
  RegisterBenchStress(*bench, result);
  RegisterBenchSupervisor(*bench, result);
  RegisterBenchSupervisorAbuse(*bench, result);
  RegisterBenchRemap(*bench, result);
  RegisterBenchPatchFlood(*bench, result);
}

}  // namespace fleetloc::fleetctl
