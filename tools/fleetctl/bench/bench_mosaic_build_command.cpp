// `fleetctl bench mosaic-build`: its options;
// the run is bench::RunMosaicBuildBench (tools/bench/harness/mosaic).
#include <memory>
#include <string>

#include "bench/bench_commands.h"
#include "harness/mosaic/bench_mosaic_build.h"

namespace fleetloc::fleetctl {

void RegisterBenchMosaicBuildCommand(CLI::App& bench, Status* result) {
  auto s = std::make_shared<bench::MosaicBuildBenchArgs>();
  CLI::App* cmd = bench.add_subcommand(
      "mosaic-build",
      "Mapping run -> mosaic build -> distortion vs the true floor -> fast run tracked on it");
  cmd->option_defaults()->always_capture_default();
  cmd->add_option("--floor", s->floor, "Floor image (default: demo rock_dirt_2048.png)");
  cmd->add_option("--resolution", s->resolution_m, "Metres per pixel of the floor image");
  cmd->add_option("--mapping-frames", s->mapping_frames, "Frames of the slow mapping run")
      ->check(CLI::Range(2, 1000000));
  cmd->add_option("--mapping-speed-px-s", s->mapping_speed_px_s, "Mapping run speed");
  cmd->add_option("--fast-frames", s->fast_frames, "Frames of the fast run tracked")
      ->check(CLI::Range(1, 1000000));
  cmd->add_option("--rate-hz", s->rate_hz, "Frame rate of both runs");
  cmd->add_option("--seed", s->seed, "Seed of the mapping run (the fast run: seed + 1)");
  cmd->add_option("--work-dir", s->work_dir, "Runs, mosaics and each step's output and log");
  cmd->add_option("--json", s->json, "Write every number to this JSON file");
  cmd->callback([s, result] { *result = bench::RunMosaicBuildBench(*s); });
}

}  // namespace fleetloc::fleetctl
