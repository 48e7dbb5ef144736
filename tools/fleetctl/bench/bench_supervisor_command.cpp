// `fleetctl bench supervisor`: its options;
// the run is bench::RunSupervisorBench (tools/bench/harness/supervisor).
#include <memory>
#include <string>

#include "bench/bench_commands.h"
#include "harness/supervisor/bench_supervisor.h"

namespace fleetloc::fleetctl {

void RegisterBenchSupervisorCommand(CLI::App& bench, Status* result) {
  auto a = std::make_shared<bench::SupervisorBenchArgs>();
  CLI::App* cmd = bench.add_subcommand(
      "supervisor",
      "Fleet supervisor under a simulated fleet: backlog, stream latency, CPU, memory");
  cmd->option_defaults()->always_capture_default();
  cmd->add_option("--vehicles", a->vehicles, "Simulated vehicles")->check(CLI::Range(1, 5000));
  cmd->add_option("--pose-hz", a->pose_hz, "Poses per vehicle per second")
      ->check(CLI::Range(0.5, 200.0));
  cmd->add_option("--seconds", a->seconds, "Measured seconds (after a 3 s warm-up)")
      ->check(CLI::Range(1.0, 3600.0));
  cmd->add_option("--domain", a->domain, "DDS domain")->check(CLI::Range(0, 232));
  cmd->add_option("--work-dir", a->work_dir, "Directory for the supervisor's history and log");
  cmd->add_option("--json", a->json, "Write every number as JSON");
  cmd->add_option("--supervisor-config", a->supervisor_config,
                  "The supervisor's configuration (JSON), e.g. with \"vda5050\" enabled");
  cmd->callback([a, result] { *result = bench::RunSupervisorBench(*a); });
}

}  // namespace fleetloc::fleetctl
