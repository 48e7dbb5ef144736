// `fleetctl bench reloc`: its options; the run is bench::RunRelocBench (with --stress over the
// stress floors), tools/bench/harness/reloc.
#include <memory>
#include <string>

#include "bench/bench_commands.h"
#include "harness/reloc/run_reloc_bench.h"

namespace fleetloc::fleetctl {
namespace {

// The options of --stress runs.
void AddStressOptions(CLI::App* cmd, bench::RelocStressArgs& st) {
  cmd->add_option("--manifest", st.manifest, "Stress floors manifest (with --stress)");
  cmd->add_option("--split", st.split, "tuning, holdout, fresh or all (with --stress)")
      ->check(CLI::IsMember({"tuning", "holdout", "fresh", "all"}));
  cmd->add_option("--classes", st.classes, "Floor classes (with --stress; default: all)")
      ->delimiter(',');
  cmd->add_option("--sizes", st.sizes, "Frame sizes WIDTHxHEIGHT (with --stress)")->delimiter(',');
  cmd->add_option("--conditions", st.conditions,
                  "Camera conditions: clean, fast, dusty, all, marks, camera (with --stress)")
      ->delimiter(',');
  cmd->add_option("--layouts", st.layouts,
                  "single (the floor alone) and/or repeated (the floor twice side by side; "
                  "with --stress)")
      ->delimiter(',');
}

// The fine dense search's options (issue 17), for measuring them.
void AddFineSearchOptions(CLI::App* cmd, relocalization::RelocalizerOptions& r) {
  cmd->add_option("--fine-sweep-step-factor", r.dense_fine.sweep_heading_step_factor,
                  "The fine dense search's sweep heading step, times its default")
      ->check(CLI::Range(1.0, 4.0))
      ->capture_default_str();
  cmd->add_option("--fine-refine-heading-steps", r.dense_fine.refine_heading_steps,
                  "Refine-level heading steps either side the fine dense search refines over")
      ->check(CLI::Range(1, 8))
      ->capture_default_str();
  cmd->add_option("--fine-min-correlation", r.dense_fine_min_correlation,
                  "The fine dense search's best peak must correlate at least this much")
      ->check(CLI::Range(0.01, 0.99))
      ->capture_default_str();
  cmd->add_option("--fine-refine-sweep", r.dense_fine_refine_sweep,
                  "When the fine dense search finds nothing, sweep its refine level itself "
                  "(true/false)")
      ->capture_default_str();
  cmd->add_option("--attempt-budget-ms", r.dense_attempt_budget_ms,
                  "The refine-level sweep runs only when the attempt stays within this (ms)")
      ->check(CLI::Range(0.0, 1e6))
      ->capture_default_str();
  cmd->add_option("--fine-refine-sweep-stride", r.dense_fine.refine_sweep_heading_stride,
                  "The fine search's refine-level sweep visits at least every this-many-th heading")
      ->check(CLI::Range(1, 4))
      ->capture_default_str();
  cmd->add_option("--fine-refine-sweep-finest-stride", r.dense_fine_refine_sweep_finest_stride,
                  "The refine-level sweep's finest stride, when its time fits the budget")
      ->check(CLI::Range(1, 4))
      ->capture_default_str();
  cmd->add_option("--fine-coarse-peaks", r.dense_fine.coarse_peaks,
                  "Distinct peaks of the fine dense search's sweep it refines")
      ->check(CLI::Range(4, 100))
      ->capture_default_str();
  cmd->add_option("--twin-contrast", r.twin_contrast,
                  "Accept a dense best told from its rivals where the mosaic's views differ "
                  "(true/false)")
      ->capture_default_str();
}

}  // namespace

void RegisterBenchRelocCommand(CLI::App& bench, Status* result) {
  auto args = std::make_shared<bench::RelocBenchArgs>();
  CLI::App* cmd = bench.add_subcommand(
      "reloc", "Global relocalization from random poses on a >= 100 Mpx non-repeating mosaic");
  cmd->option_defaults()->always_capture_default();
  cmd->add_option("--mosaic", args->mosaic, "Use this mosaic instead of composing one");
  cmd->add_option("--size", args->size, "Composed floor size WIDTHxHEIGHT (without --mosaic)");
  cmd->add_option("--floors-dir", args->floors_dir, "Floor photos to compose from");
  cmd->add_option("--work-dir", args->work_dir, "Where the composed mosaic is kept");
  cmd->add_option("--json", args->json, "Write every number to this JSON file");
  cmd->add_option("--trials", args->trials.trials, "Random poses")->check(CLI::Range(1, 100000));
  cmd->add_option("--attempts", args->trials.attempts, "Frames tried per trial")
      ->check(CLI::Range(1, 50));
  cmd->add_option("--seed", args->trials.seed, "Floor composition, poses and rendering seed");
  cmd->add_option("--lsh-tables", args->index.lsh_tables, "LSH hash tables");
  cmd->add_option("--lsh-key-bits", args->index.lsh_key_bits, "LSH key bits");
  cmd->add_option("--lsh-multiprobe", args->index.lsh_multiprobe_level, "LSH multi-probe level");
  cmd->add_option("--max-verified", args->trials.relocalizer.max_verified_candidates,
                  "Candidates verified by a tracker cycle per frame");
  cmd->add_option("--trajectory-frames", args->trials.relocalizer.trajectory_frames,
                  "Frames combined with odometry when one is not enough (1: single frames; "
                  "reports both)")
      ->check(CLI::Range(1, 20))
      ->capture_default_str();
  cmd->add_option("--threads", args->trials.threads,
                  "OpenCV threads while a frame is relocalized (the dense searches' heading pairs "
                  "on 2 stripes; results do not depend on it)")
      ->check(CLI::Range(1, 2))
      ->capture_default_str();
  AddFineSearchOptions(cmd, args->trials.relocalizer);
  cmd->add_flag("--trajectory-refine-level", args->trials.relocalizer.trajectory_refine_level,
                "Sum the frames' heading sweeps at the dense search's refine level (slower)");
  cmd->add_option("--trajectory-max-mb", args->trials.relocalizer.trajectory_max_mb,
                  "Memory bound of the summed sweeps (multi-frame off above it)")
      ->check(CLI::Range(1.0, 4096.0))
      ->capture_default_str();
  cmd->add_flag("--stress", args->stress,
                "The stress floors (data/stress_floors) × --sizes × --conditions × --layouts "
                "instead of one large composed floor");
  AddStressOptions(cmd, args->stressed);
  cmd->callback([args, result] { *result = bench::RunRelocBench(*args); });
}

}  // namespace fleetloc::fleetctl
