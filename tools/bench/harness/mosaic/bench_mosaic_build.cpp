// The mosaic-build benchmark: each step as a child fleetctl process, the distortion in-process.
#include "harness/mosaic/bench_mosaic_build.h"

#include <spdlog/spdlog.h>

#include <cmath>
#include <iomanip>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "harness/common/fleetctl_rerun.h"
#include "harness/mosaic/bench_mosaic_distortion.h"
#include "harness/tracker/bench_tracker.h"
#include "io/file_util.h"
#include "mosaic/mosaic_view.h"
#include "mosaic/tile_store.h"
#include "run_io/run.h"
#include "support/floor_images.h"

namespace fleetloc::bench {
namespace {

namespace fs = std::filesystem;

struct Step {
  RerunResult run;
  nlohmann::json out;  // the step's JSON on stdout
};

std::string Joined(const std::vector<std::string>& args) {
  std::string line;
  for (const std::string& arg : args) line += (line.empty() ? "" : " ") + arg;
  return line;
}

std::string LastLine(const std::string& text) {
  const std::size_t end = text.find_last_not_of('\n');
  if (end == std::string::npos) return "";
  const std::size_t begin = text.rfind('\n', end);
  return text.substr(begin == std::string::npos ? 0 : begin + 1, end + 1 - (begin + 1));
}

// Runs one fleetctl step with its stdout and stderr in the work directory; stdout, when there is
// any, must be JSON. Internal naming the step and its last log line when it fails.
Result<Step> RunStep(const std::string& name, const std::vector<std::string>& args,
                     const fs::path& work) {
  spdlog::info("bench: {}: fleetctl {}", name, Joined(args));
  const fs::path out = work / (name + ".json"), err = work / (name + ".log");
  Result<RerunResult> run = RunFleetctlChild(args, out, err);
  if (!run.ok()) return run.status();
  if (run->exit_code != 0) {
    Result<std::string> log = io::ReadFileText(err);
    return Internal("bench step '" + name + "' failed (exit " + std::to_string(run->exit_code) +
                    ", log " + err.string() + "): " + (log.ok() ? LastLine(*log) : ""));
  }
  Result<std::string> text = io::ReadFileText(out);
  if (!text.ok()) return text.status();
  Step step{*run, nlohmann::json::parse(*text, nullptr, /*allow_exceptions=*/false)};
  if (step.out.is_discarded()) step.out = nlohmann::json::object();
  return step;
}

std::vector<std::string> SimArgs(const MosaicBuildBenchArgs& s, const fs::path& out, int frames,
                                 int seed) {
  return {"sim",
          "--image",
          s.floor,
          "--resolution",
          std::to_string(s.resolution_m),
          "--rate-hz",
          std::to_string(s.rate_hz),
          "--frames",
          std::to_string(frames),
          "--seed",
          std::to_string(seed),
          "--out",
          out.string(),
          "--overwrite"};
}

void RemoveMosaic(const fs::path& db) {
  std::error_code ec;
  for (const char* suffix : {"", "-wal", "-shm", ".partial"}) fs::remove(db.string() + suffix, ec);
}

// A JSON number with `digits` decimals, for the report.
std::string Fixed(const nlohmann::json& value, int digits) {
  std::ostringstream out;
  out << std::fixed << std::setprecision(digits) << value.get<double>();
  return out.str();
}

void PrintReport(const MosaicBuildBenchArgs& s, const nlohmann::json& j) {
  const nlohmann::json& b = j["build"];
  const nlohmann::json& m = b["summary"];
  const nlohmann::json& d = j["distortion"];
  std::cout << "== mosaic build from a mapping run: " << fs::path(s.floor).filename().string()
            << " at " << s.resolution_m << " m/px; " << s.mapping_frames << " frames at "
            << s.mapping_speed_px_s << " px/s, " << s.rate_hz << " Hz, figure8, seed " << s.seed
            << "\n";
  std::cout << "build: " << Fixed(b["wall_s"], 1) << " s wall, " << Fixed(b["cpu_s"], 1)
            << " s CPU (wall: mapping " << Fixed(m["seconds"]["mapping"], 1) << ", blending "
            << Fixed(m["seconds"]["blending"], 1) << ", tiles " << Fixed(m["seconds"]["writing"], 1)
            << "), peak RSS " << b["peak_rss_bytes"].get<long long>() / (1 << 20) << " MiB (canvas "
            << m["canvas_bytes"].get<long long>() / (1 << 20) << " MiB); " << m["pairs_registered"]
            << "/" << m["pairs_tried"] << " pairs registered, " << m["loop_closures"]
            << " loop closures (" << m["loop_closures_pruned"] << " pruned); mosaic "
            << m["mosaic_px"][0] << "x" << m["mosaic_px"][1] << " px\n";
  if (m.contains("truth")) {
    std::cout << "mapped poses vs truth: camera position RMS "
              << Fixed(m["truth"]["camera_position_rms_px"], 3) << " px, max "
              << Fixed(m["truth"]["camera_position_max_px"], 3) << " px\n";
  }
  std::cout << "local distortion vs the true floor (" << d["patches"] << " patches): RMS "
            << Fixed(d["rms_px"], 3) << " px, max " << Fixed(d["max_px"], 3) << " px; scale error "
            << Fixed(d["scale_error_ppm"], 1) << " ppm, rotation " << Fixed(d["rotation_mrad"], 3)
            << " mrad; without them RMS " << Fixed(d["residual_rms_px"], 3) << " px, max "
            << Fixed(d["residual_max_px"], 3) << " px\n";
  for (const char* mosaic : {"built", "imported"}) {
    const nlohmann::json& t = j["track"][mosaic];
    std::cout << "fast run (" << s.fast_frames << " frames, seed " << s.seed + 1
              << ") tracked on the " << mosaic << " mosaic: lock rate " << Fixed(t["lock_rate"], 3)
              << ", camera position RMS " << Fixed(t["error"]["camera_position_rms_px"], 3)
              << " px, p95 " << Fixed(t["error"]["camera_position_p95_px"], 3) << " px\n";
  }
}

nlohmann::json SettingsJson(const MosaicBuildBenchArgs& s, const fs::path& work) {
  return {{"floor", s.floor},
          {"resolution_m", s.resolution_m},
          {"mapping_frames", s.mapping_frames},
          {"mapping_speed_px_s", s.mapping_speed_px_s},
          {"fast_frames", s.fast_frames},
          {"rate_hz", s.rate_hz},
          {"seed", s.seed},
          {"work_dir", work.string()}};
}

// The slow mapping run, `mosaic build` on it and the built mosaic's distortion, into *json.
Status MapAndBuild(const MosaicBuildBenchArgs& s, const fs::path& work, nlohmann::json* json) {
  const fs::path mapping_run = work / "mapping_run", built = work / "built.db";
  std::vector<std::string> mapping_sim = SimArgs(s, mapping_run, s.mapping_frames, s.seed);
  mapping_sim.insert(mapping_sim.end(), {"--speed-px-s", std::to_string(s.mapping_speed_px_s),
                                         "--route", "figure8", "--no-initial-perturb"});
  Result<Step> sim = RunStep("sim_mapping", mapping_sim, work);
  if (!sim.ok()) return sim.status();
  RemoveMosaic(built);
  Result<Step> build =
      RunStep("mosaic_build",
              {"mosaic", "build", "--run", mapping_run.string(), "--out", built.string()}, work);
  if (!build.ok()) return build.status();
  Result<mapping::DistortionReport> distortion =
      MeasureBuiltMosaicDistortion(built, s.floor, s.resolution_m);
  if (!distortion.ok()) return distortion.status();
  (*json)["mapping_sim"] = sim->out;
  (*json)["build"] = {{"wall_s", build->run.wall_s},
                      {"cpu_s", build->run.cpu_s},
                      {"peak_rss_bytes", build->run.peak_rss_bytes},
                      {"summary", build->out}};
  (*json)["distortion"] = DistortionJson(*distortion);
  return Status::Ok();
}

// The fast run, tracked on the built mosaic and on the floor imported directly, into *json.
Status TrackFastRun(const MosaicBuildBenchArgs& s, const fs::path& work, nlohmann::json* json) {
  const fs::path fast_run = work / "fast_run", imported = work / "imported.db";
  Result<Step> fast = RunStep("sim_fast", SimArgs(s, fast_run, s.fast_frames, s.seed + 1), work);
  if (!fast.ok()) return fast.status();
  RemoveMosaic(imported);
  Result<Step> import = RunStep("mosaic_import",
                                {"mosaic", "import", s.floor, "--resolution",
                                 std::to_string(s.resolution_m), "--out", imported.string()},
                                work);
  if (!import.ok()) return import.status();
  for (const char* name : {"built", "imported"}) {
    const std::string mosaic = (work / (std::string(name) + ".db")).string();
    const std::string poses = (work / (std::string("poses_") + name + ".csv")).string();
    Result<Step> track =
        RunStep(std::string("track_") + name,
                {"track", "--mosaic", mosaic, "--run", fast_run.string(), "--out", poses}, work);
    if (!track.ok()) return track.status();
    (*json)["track"][name] = track->out;
  }
  return Status::Ok();
}

}  // namespace

Status RunMosaicBuildBench(MosaicBuildBenchArgs s) {
  if (s.floor.empty()) s.floor = (fleetctl::DefaultFloorsDir() / "rock_dirt_2048.png").string();
  const fs::path work = io::AbsoluteDir(s.work_dir);
  std::error_code ec;
  fs::create_directories(work, ec);
  if (ec) return Internal(work.string() + ": cannot create: " + ec.message());
  nlohmann::json json{{"settings", SettingsJson(s, work)}};
  FLEETLOC_RETURN_IF_ERROR(MapAndBuild(s, work, &json));
  FLEETLOC_RETURN_IF_ERROR(TrackFastRun(s, work, &json));
  PrintReport(s, json);
  if (s.json.empty()) return Status::Ok();
  return io::WriteFileAtomically(s.json, json.dump(2) + "\n");
}

}  // namespace fleetloc::bench
