// fleetctl remap: asks the running map servers (over DDS) to fold the stored patches of a map
// region into a new mosaic version, follows the job's RemapStatus from every server reading the
// command (each keeps its own replica when the mosaic is split across servers) and prints the
// outcome as JSON: the worst server's outcome at the top (a single server's, as before), and every
// server's under "servers".
#include <spdlog/spdlog.h>

#include <chrono>
#include <iostream>
#include <map>
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

using Clock = std::chrono::steady_clock;

// How many map servers read our commands: waits for the first, then until the count has held
// for `settle` (the others are discovered within moments of the first), bounded by `deadline`.
Result<int> WaitForServers(const transport::RemapClient& client, const RemapArgs& a,
                           Clock::time_point deadline) {
  constexpr auto kSettle = std::chrono::milliseconds(700);
  while (client.MatchedServers() == 0) {
    if (Clock::now() > deadline)
      return Internal("no map server on domain " + std::to_string(a.domain));
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  int servers = client.MatchedServers();
  for (auto steady_since = Clock::now();
       Clock::now() - steady_since < kSettle && Clock::now() < deadline;) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    if (client.MatchedServers() != servers)
      servers = client.MatchedServers(), steady_since = Clock::now();
  }
  return servers;
}

// Rejected is worse than failed, failed worse than done.
const transport::RemapProgress& Worst(
    const std::map<std::string, transport::RemapProgress>& finals) {
  const transport::RemapProgress* worst = &finals.begin()->second;
  for (const auto& [server, s] : finals) {
    if (s.state > worst->state) worst = &s;
  }
  return *worst;
}

nlohmann::json Outcome(const transport::RemapProgress& s) {
  nlohmann::json out = ToJson(s);
  out.erase("phase"), out.erase("progress"), out.erase("t");
  return out;
}

// Sends the command once the map servers listen, then follows their statuses until each is done,
// failed or rejected, or the time-out.
Status RunRemap(const RemapArgs& a) {
  if (a.region.size() != 4) return InvalidInput("--region: give x_min,y_min,x_max,y_max");
  using namespace transport;
  auto participant = Participant::Create(a.domain, {"", a.dds_config});
  if (!participant.ok()) return participant.status();
  auto client = RemapClient::Create(*participant);
  if (!client.ok()) return client.status();
  const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                           std::chrono::duration<double>(a.timeout_s));
  Result<int> servers = WaitForServers(**client, a, deadline);
  if (!servers.ok()) return servers.status();
  const RemapRequest request{a.region[0], a.region[1], a.region[2], a.region[3],
                             a.mode == "replace", a.mosaic_id, "fleetctl"};
  Result<uint64_t> id = (*client)->Send(request);
  if (!id.ok()) return id.status();
  spdlog::info("remap: command {} sent to {} map server(s)", *id, *servers);
  std::map<std::string, RemapProgress> finals;  // by server id
  while (static_cast<int>(finals.size()) < *servers && Clock::now() < deadline) {
    Result<std::vector<RemapProgress>> statuses = (*client)->TakeStatuses();
    if (!statuses.ok()) return statuses.status();
    for (const RemapProgress& s : *statuses) {
      if (s.command_id != *id) continue;
      spdlog::info("remap: {} {} {} {:.0f}%", s.server_id, RemapStateName(s.state), s.phase,
                   100 * s.progress);
      if (s.final()) finals.emplace(s.server_id, s);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  if (static_cast<int>(finals.size()) < *servers) {
    return Internal("remap: " + std::to_string(finals.size()) + " of " + std::to_string(*servers) +
                    " map servers gave a final status within " + std::to_string(a.timeout_s) +
                    " s");
  }
  const RemapProgress& worst = Worst(finals);
  nlohmann::json out = Outcome(worst);
  out["servers"] = nlohmann::json::array();
  for (const auto& [server, s] : finals) out["servers"].push_back(Outcome(s));
  std::cout << out.dump(2) << "\n";
  if (worst.state == fleetloc_REMAP_REJECTED)
    return InvalidInput("remap rejected by " + worst.server_id + ": " + worst.message);
  if (worst.state == fleetloc_REMAP_FAILED)
    return Internal("remap failed on " + worst.server_id + ": " + worst.message);
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
