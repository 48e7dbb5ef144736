// `fleetctl bench tracker-stress`: its options;
// the run is bench::RunTrackerStressBench (tools/bench/harness/stress).
#include <memory>
#include <string>

#include "bench/bench_commands.h"
#include "harness/stress/run_stress_bench.h"

namespace fleetloc::fleetctl {

void RegisterBenchTrackerStressCommand(CLI::App& bench, Status* result) {
  auto args = std::make_shared<bench::TrackerStressBenchArgs>();
  CLI::App* stress = bench.add_subcommand(
      "tracker-stress",
      "The tracker and its peers on the stress floors (data/stress_floors) at several frame "
      "sizes and camera conditions; each split (tuning, holdout, fresh) reported apart");
  bench::BenchSettings& s = args->settings;
  s.frames = 150;
  s.peer_frames = 20;
  s.methods = {"fleetloc", "ecc", "orb", "sift"};
  s.timing_replays = 3;
  stress->add_option("--manifest", args->manifest,
                     "Floors manifest (default: data/stress_floors/floors.json)");
  stress->add_option("--split", args->split, "tuning, holdout, fresh or all")
      ->check(CLI::IsMember({"tuning", "holdout", "fresh", "all"}));
  stress->add_option("--classes", args->classes, "Floor classes to run (default: all)")
      ->delimiter(',');
  stress->add_option("--sizes", args->sizes, "Frame sizes WIDTHxHEIGHT")->delimiter(',');
  stress
      ->add_option("--conditions", args->conditions,
                   "clean, fast, dusty, all, marks, camera (default: these six); aisles")
      ->delimiter(',');
  stress->add_option("--frames", s.frames, "Frames per cell")->check(CLI::Range(1, 1000000));
  stress
      ->add_option("--peer-frames", s.peer_frames, "Peers replay only the first N frames (0: all)")
      ->check(CLI::Range(0, 1000000));
  stress->add_option("--methods", s.methods, "fleetloc and peers (ecc, orb, sift, phase)")
      ->delimiter(',');
  AddTimingReplaysOption(stress, &s.timing_replays);
  stress->add_option("--seed", s.seed, "Simulation seed");
  stress->add_option("--work-dir", args->work_dir, "Scaled floors, mosaics and runs");
  stress->add_option("--json", args->json, "Write every number to this JSON file");
  stress->add_option("--tracker-config", args->tracker_config,
                     "fleetloc's tracker options (JSON, as fleetctl track --config)");
  stress->callback([args, result] { *result = bench::RunTrackerStressBench(*args); });
}

}  // namespace fleetloc::fleetctl
