// `fleetctl bench supervisor-abuse`: its options;
// the run is bench::RunSupervisorAbuseBench (tools/bench/harness/supervisor).
#include <memory>
#include <string>

#include "bench/bench_commands.h"
#include "harness/supervisor/bench_supervisor_abuse.h"

namespace fleetloc::fleetctl {

void RegisterBenchSupervisorAbuseCommand(CLI::App& bench, Status* result) {
  auto a = std::make_shared<bench::SupervisorAbuseBenchArgs>();
  CLI::App* cmd = bench.add_subcommand(
      "supervisor-abuse",
      "Fleet supervisor's API latency and memory under idle, streaming, slow and flooding clients");
  cmd->option_defaults()->always_capture_default();
  cmd->add_option("--idle", a->abuse.idle, "Idle sockets")->check(CLI::Range(0, 100000));
  cmd->add_option("--streams", a->abuse.streams, "Live streams (/api/events), half never read")
      ->check(CLI::Range(0, 100000));
  cmd->add_option("--slow", a->abuse.slow, "Slow senders (one byte of an endless head per 100 ms)")
      ->check(CLI::Range(0, 100000));
  cmd->add_option("--flood-mb", a->abuse.flood_mb, "Header bytes to flood, MB")
      ->check(CLI::Range(0.0, 100000.0));
  cmd->add_option("--seconds", a->seconds, "Measured seconds under attack")
      ->check(CLI::Range(1.0, 3600.0));
  cmd->add_option("--idle-seconds", a->idle_seconds, "Measured seconds before the attack")
      ->check(CLI::Range(1.0, 3600.0));
  cmd->add_option("--requests-hz", a->requests_hz,
                  "Operator requests per second (one GET and one POST each)")
      ->check(CLI::Range(0.1, 100.0));
  cmd->add_option("--domain", a->domain, "DDS domain")->check(CLI::Range(0, 232));
  cmd->add_option("--work-dir", a->work_dir, "Directory for the mosaic, history and logs");
  cmd->add_option("--json", a->json, "Write every number as JSON");
  cmd->callback([a, result] { *result = bench::RunSupervisorAbuseBench(*a); });
}

}  // namespace fleetloc::fleetctl
