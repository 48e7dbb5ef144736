// `fleetctl bench mosaic`: its options;
// the run is bench::RunMosaicBench (tools/bench/harness/mosaic).
#include <memory>
#include <string>

#include "bench/bench_commands.h"
#include "harness/mosaic/run_mosaic_bench.h"
#include "support/floor_images.h"

namespace fleetloc::fleetctl {

void RegisterBenchMosaicCommand(CLI::App& bench, Status* result) {
  auto args = std::make_shared<bench::MosaicBenchArgs>();
  bench::MosaicBenchSettings& s = args->settings;
  CLI::App* cmd = bench.add_subcommand(
      "mosaic", "Mosaic store at scale: import time and peak RSS, tile and block lookup latency");
  cmd->option_defaults()->always_capture_default();
  cmd->add_option("--sizes", args->sizes, "Image sizes WIDTHxHEIGHT, comma-separated")
      ->delimiter(',');
  cmd->add_option("--floors-dir", args->floors_dir,
                  "Floor photos to compose from (default: the source tree's " +
                      std::string(kFloorsSubdir) + ")");
  cmd->add_option("--work-dir", args->work_dir, "Composed floors and mosaics, one dir per size");
  cmd->add_option("--json", args->json, "Write every number to this JSON file");
  cmd->add_option("--block", s.block_px, "Composition block side, px")->check(CLI::Range(16, 4096));
  cmd->add_option("--seed", s.seed, "Composition and sampling seed");
  cmd->add_option("--tile-samples", args->tile_samples, "Random tiles read, each way, per size")
      ->check(CLI::Range(1, 10000000));
  cmd->add_option("--block-samples", args->block_samples,
                  "Random blocks read cold and warm, per size")
      ->check(CLI::Range(1, 10000000));
  cmd->add_option("--rounds", args->rounds,
                  "Lookup rounds taking the sizes in turn (samples split between rounds)")
      ->check(CLI::Range(1, 1000));
  cmd->add_flag("--keep-files", s.keep_files, "Keep each size's PGM and mosaic");
  cmd->callback([args, result] { *result = bench::RunMosaicBench(*args); });
}

}  // namespace fleetloc::fleetctl
