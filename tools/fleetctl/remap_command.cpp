// fleetctl remap: asks the running map server (over DDS) to fold the stored patches of a map
// region into a new mosaic version, follows the job's RemapStatus and prints the outcome as JSON.
#include <spdlog/spdlog.h>

#include <chrono>
#include <iostream>
#include <nlohmann/json.hpp>
#include <thread>

#include "commands.h"
#include "transport/remap_client.h"

namespace fleetloc::fleetctl {
namespace {

struct RemapArgs {
  std::vector<double> region;  // x_min, y_min, x_max, y_max (map metres)
  std::string mode = "blend";
  std::string mosaic_id;
  int domain = 0;
  std::string dds_config;
  double timeout_s = 600;
};

// Sends the command once a map server listens, then follows its status until done, failed,
// rejected or the time-out.
Status RunRemap(const RemapArgs& a) {
  if (a.region.size() != 4) return InvalidInput("--region: give x_min,y_min,x_max,y_max");
  using namespace transport;
  auto participant = Participant::Create(a.domain, {"", a.dds_config});
  if (!participant.ok()) return participant.status();
  auto client = RemapClient::Create(*participant);
  if (!client.ok()) return client.status();
  using Clock = std::chrono::steady_clock;
  const auto deadline = Clock::now() + std::chrono::duration<double>(a.timeout_s);
  while (!(*client)->ServerMatched()) {
    if (Clock::now() > deadline) return Internal("no map server on domain " + std::to_string(a.domain));
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  const RemapRequest request{a.region[0], a.region[1], a.region[2], a.region[3],
                             a.mode == "replace", a.mosaic_id, "fleetctl"};
  Result<uint64_t> id = (*client)->Send(request);
  if (!id.ok()) return id.status();
  spdlog::info("remap: command {} sent", *id);
  std::optional<RemapProgress> final;
  while (!final && Clock::now() < deadline) {
    Result<std::vector<RemapProgress>> statuses = (*client)->TakeStatuses();
    if (!statuses.ok()) return statuses.status();
    for (const RemapProgress& s : *statuses) {
      if (s.command_id != *id) continue;
      spdlog::info("remap: {} {} {:.0f}%", RemapStateName(s.state), s.phase, 100 * s.progress);
      if (s.final()) final = s;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  if (!final) return Internal("remap: no final status within " + std::to_string(a.timeout_s) + " s");
  nlohmann::json out = ToJson(*final);
  out.erase("phase"), out.erase("progress"), out.erase("t");
  std::cout << out.dump(2) << "\n";
  if (final->state == fleetloc_REMAP_REJECTED) return InvalidInput("remap rejected: " + final->message);
  if (final->state == fleetloc_REMAP_FAILED) return Internal("remap failed: " + final->message);
  return Status::Ok();
}

}  // namespace

void RegisterRemapCommand(CLI::App& app, Status* result) {
  auto a = std::make_shared<RemapArgs>();
  CLI::App* remap = app.add_subcommand(
      "remap", "Fold the stored patches of a map region into a new mosaic version (over DDS)");
  remap->option_defaults()->always_capture_default();
  remap->add_option("--region", a->region, "X_MIN,Y_MIN,X_MAX,Y_MAX in map metres")
      ->required()
      ->delimiter(',')
      ->expected(4);
  remap->add_option("--mode", a->mode, "blend (average with the mosaic) or replace (changed floor)")
      ->check(CLI::IsMember({"blend", "replace"}));
  remap->add_option("--mosaic-id", a->mosaic_id, "Mosaic id (default: the one the server serves)");
  remap->add_option("--domain", a->domain, "DDS domain")->check(CLI::Range(0, 232));
  remap->add_option("--dds-config", a->dds_config, "Cyclone DDS XML (default: built-in loopback)");
  remap->add_option("--timeout", a->timeout_s, "Seconds to wait for the job")->check(CLI::PositiveNumber);
  remap->callback([a, result] { *result = RunRemap(*a); });
}

}  // namespace fleetloc::fleetctl
