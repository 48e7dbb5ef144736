// fleetctl track: run the vehicle tracker offline over a run, exactly as the agent would; write
// poses.csv and print a JSON summary (docs/cli.md).
#include <spdlog/spdlog.h>

#include <iostream>
#include <map>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "io/file_util.h"
#include "mosaic/tile_store.h"
#include "replay/replay.h"
#include "run_io/tracker_config.h"
#include "support/tracker_summary.h"
#include "tracking/camera_scale_check.h"
#include "tracking/mosaic_tracker.h"

namespace fleetloc::fleetctl {
namespace {

struct TrackArgs {
  std::string mosaic;
  std::string run;
  std::string out;
  std::string config;
  std::string frames_out;
  long long cache_mb = 256;
};

}  // namespace

Result<replay::ReplayResult> TrackOffline(const std::string& mosaic_path, const run_io::Run& run,
                                          const tracking::TrackerOptions& options,
                                          long long cache_mb) {
  Result<std::unique_ptr<mosaic::TileStore>> opened =
      mosaic::TileStore::Open(mosaic_path, mosaic::OpenMode::kReadOnly);
  if (!opened.ok()) return opened.status();
  std::shared_ptr<mosaic::TileStore> store = std::move(*opened);
  FLEETLOC_RETURN_IF_ERROR(
      tracking::CheckCameraResolution(run.camera.model.resolution_m, store->layout().geo.resolution,
                                      (run.dir / "run.json").string() + " (its camera)"));
  mosaic::MosaicView view(store->layout(), mosaic::MakeTileLoader(store),
                          std::make_shared<mosaic::TileCache>(cache_mb << 20));
  tracking::MosaicTracker tracker(options, run.camera.model, &view);
  return replay::ReplayRun(run, tracker, [](size_t done, size_t total) {
    if (done % 200 == 0 || done == total) spdlog::info("tracked {}/{} frames", done, total);
  });
}

namespace {

// One line per frame: what the tracker did with it (lock state, templates, the dense alignment
// and why it refused), for finding out why a run coasts.
std::string FramesCsv(const replay::ReplayResult& replayed) {
  std::string csv =
      "t,status,templates,template_size_px,inliers,rms_residual_px,search_radius_px,select_ms,"
      "coarse_ms,fine_ms,"
      "direct_ms,direct,direct_reason,direct_correlation,direct_coarse_correlation,direct_peak_"
      "ratio,"
      "direct_chi2,cycle_ms,polish_ms,polished,direct_peak_z,direct_sigma_px,view_blur_px,"
      "direct_searches,direct_iterations\n";
  for (size_t i = 0; i < replayed.frames.size(); ++i) {
    const tracking::FrameResult& f = replayed.frames[i];
    csv += fmt::format(
        "{:.6f},{},{},{},{},{:.4f},{},{:.3f},{:.3f},{:.3f},{:.3f},{},\"{}\",{:.3f},{:.3f},{:.3f},{:"
        "."
        "2f},{:.3f},{:.3f},{},{:.2f},{:.4f},{:.2f},{},{}\n",
        f.t, tracking::LockStateName(f.state), f.templates, f.template_size_px, f.inliers,
        f.rms_residual_px, f.search_radius_px, f.select_ms, f.coarse_ms, f.fine_ms, f.direct_ms,
        tracking::DirectUseName(f.direct), f.direct_reason, f.direct_correlation,
        f.direct_coarse_correlation, f.direct_peak_ratio, f.direct_chi2, replayed.cycle_ms[i],
        f.polish_ms, f.polished ? 1 : 0, f.direct_peak_z, f.direct_sigma_px, f.view_blur_px,
        f.direct_searches, f.direct_iterations);
  }
  return csv;
}

Status RunTrack(const TrackArgs& args) {
  Result<run_io::Run> run = run_io::ReadRun(args.run);
  if (!run.ok()) return run.status();
  tracking::TrackerOptions options;
  if (!args.config.empty()) {
    Result<tracking::TrackerOptions> configured = run_io::ReadTrackerOptions(args.config);
    if (!configured.ok()) return configured.status();
    options = *configured;
  }
  Result<replay::ReplayResult> replayed = TrackOffline(args.mosaic, *run, options, args.cache_mb);
  if (!replayed.ok()) return replayed.status();
  FLEETLOC_RETURN_IF_ERROR(run_io::WritePosesCsv(args.out, replayed->poses));
  if (!args.frames_out.empty()) {
    FLEETLOC_RETURN_IF_ERROR(io::WriteFileAtomically(args.frames_out, FramesCsv(*replayed)));
  }
  std::cout << TrackSummary(*run, *replayed).dump(2) << "\n";
  return Status::Ok();
}

}  // namespace

void RegisterTrackCommand(CLI::App& app, Status* result) {
  auto args = std::make_shared<TrackArgs>();
  CLI::App* track = app.add_subcommand("track", "Track a run offline against a mosaic");
  track->add_option("--mosaic", args->mosaic, "Mosaic file (SQLite)")->required();
  track->add_option("--run", args->run, "Run directory (docs/formats.md)")->required();
  track->add_option("--out", args->out, "Output poses.csv")->required();
  track->add_option("--config", args->config, "Tracker options (JSON; defaults for absent keys)");
  track->add_option("--frames-out", args->frames_out,
                    "Also write each frame's tracker diagnostics (CSV: lock state, templates, "
                    "inliers, timings, the dense alignment's use and refusal reason)");
  track->add_option("--cache-mb", args->cache_mb, "Tile cache bound in MiB")
      ->check(CLI::Range(1, 1 << 20));
  track->callback([args, result] { *result = RunTrack(*args); });
}

}  // namespace fleetloc::fleetctl
