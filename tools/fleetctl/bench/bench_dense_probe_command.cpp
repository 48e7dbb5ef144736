// `fleetctl bench dense-probe`: its options;
// the run is bench::RunDenseProbe (tools/bench/harness/reloc).
#include <memory>
#include <string>

#include "bench/bench_commands.h"
#include "harness/reloc/run_dense_probe.h"

namespace fleetloc::fleetctl {

void RegisterBenchDenseProbeCommand(CLI::App& bench, Status* result) {
  auto args = std::make_shared<bench::DenseProbeArgs>();
  CLI::App* cmd = bench.add_subcommand(
      "dense-probe", "The dense place search on a run's frames: correlation at the truth, peaks");
  cmd->option_defaults()->always_capture_default();
  cmd->add_option("--mosaic", args->mosaic, "Mosaic (SQLite tile store)")->required();
  cmd->add_option("--run", args->run, "Run directory with truth.csv")->required();
  cmd->add_option("--every", args->every, "Every k-th frame")->check(CLI::Range(1, 100000));
  cmd->add_option("--min-short-side", args->dense.min_short_side_px,
                  "Refine level: the coarsest whose frame short side is >= this");
  cmd->add_option("--heading-step-scale", args->dense.heading_step_scale,
                  "Heading step in frame half-diagonal pixels of the sweep level");
  cmd->add_option("--max-refine-mpx", args->dense.max_refine_level_mpx,
                  "Largest mosaic at the refine level (Mpx)");
  cmd->callback([args, result] { *result = bench::RunDenseProbe(*args); });
}

}  // namespace fleetloc::fleetctl
