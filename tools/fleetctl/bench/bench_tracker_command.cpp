// `fleetctl bench tracker`: its options; the run is bench::RunTrackerBench (tools/bench/harness).
#include <memory>
#include <string>

#include "bench/bench_commands.h"
#include "harness/tracker/run_tracker_bench.h"
#include "support/floor_images.h"

namespace fleetloc::fleetctl {
namespace {

void AddTrackerOptions(CLI::App* tracker, bench::TrackerBenchArgs* a) {
  bench::BenchSettings& s = a->settings;
  s.methods = bench::BenchMethodNames();
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
  AddTimingReplaysOption(tracker, &s.timing_replays);
}

}  // namespace

void RegisterBenchTrackerCommand(CLI::App& bench, Status* result) {
  auto args = std::make_shared<bench::TrackerBenchArgs>();
  CLI::App* tracker = bench.add_subcommand(
      "tracker", "fleetloc's tracker against the OpenCV peers on simulated runs over real floors");
  tracker->option_defaults()->always_capture_default();
  AddTrackerOptions(tracker, args.get());
  tracker->callback([args, result] { *result = bench::RunTrackerBench(*args); });
}

void AddTimingReplaysOption(CLI::App* command, int* replays) {
  command
      ->add_option("--timing-replays", *replays,
                   "fleetloc replays each run N times (the same poses each time); a frame's time "
                   "is the least of its N")
      ->capture_default_str()
      ->check(CLI::Range(1, 20));
}

}  // namespace fleetloc::fleetctl
