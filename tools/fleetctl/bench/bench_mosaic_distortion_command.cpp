// `fleetctl bench mosaic-distortion`: its options;
// the run is bench::RunMosaicDistortionBench (tools/bench/harness/mosaic).
#include <memory>
#include <string>

#include "bench/bench_commands.h"
#include "harness/mosaic/bench_mosaic_distortion.h"

namespace fleetloc::fleetctl {

void RegisterBenchMosaicDistortionCommand(CLI::App& bench, Status* result) {
  auto args = std::make_shared<bench::MosaicDistortionBenchArgs>();
  CLI::App* cmd = bench.add_subcommand(
      "mosaic-distortion", "Local distortion of a mosaic against the true floor image (JSON)");
  cmd->add_option("--mosaic", args->mosaic, "Built mosaic")->required();
  cmd->add_option("--truth", args->truth,
                  "True floor image, top-left corner at map (0, height * resolution)")
      ->required();
  cmd->add_option("--resolution", args->resolution_m, "Metres per pixel of the image")
      ->capture_default_str();
  cmd->callback([args, result] { *result = bench::RunMosaicDistortionBench(*args); });
}

}  // namespace fleetloc::fleetctl
