// `fleetctl bench mapfit`: its options;
// the run is bench::RunMapFitBench (tools/bench/harness/mapfit).
#include <memory>
#include <string>

#include "bench/bench_commands.h"
#include "harness/mapfit/bench_mapfit.h"

namespace fleetloc::fleetctl {

void RegisterBenchMapfitCommand(CLI::App& bench, Status* result) {
  auto args = std::make_shared<bench::MapFitBenchArgs>();
  CLI::App* command =
      bench.add_subcommand("mapfit", "Map fit: mean shift vs RANSAC vs ICP on the same problems");
  command->option_defaults()->always_capture_default();
  command->add_option("--kind", args->problems.kind, "Problems: corridor or rooms");
  command->add_option("--trials", args->trials, "Problems per outlier level and seed")
      ->check(CLI::Range(1, 1000000));
  command->add_option("--seed", args->seeds, "Simulation seeds (the tuning table)")->delimiter(',');
  command
      ->add_option("--held-out-seed", args->held_out_seeds,
                   "Seeds kept out of tuning, reported in a table of their own")
      ->delimiter(',');
  command
      ->add_option("--outliers", args->outlier_percents,
                   "Outlier percentages (default 50,70,80,90 corridor; 70,80,90 rooms)")
      ->delimiter(',')
      ->check(CLI::Range(0.0, 99.0));
  command->add_option("--map-landmarks", args->problems.map_landmarks,
                      "rooms: landmarks in each building");
  command
      ->add_option("--points", args->problems.points,
                   "rooms: exactly this many points per problem (0: 8-12 inliers per seen "
                   "landmark and the outliers to match)")
      ->check(CLI::Range(0, 100000));
  command->callback([args, result] { *result = bench::RunMapFitBench(*args); });
}

}  // namespace fleetloc::fleetctl
