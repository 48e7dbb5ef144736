// fleetctl remap: asks the running map servers (over DDS) to fold the stored patches of a map
// region into a new mosaic version, follows the job's RemapStatus from every server announcing the
// mosaic (each keeps its own replica when the mosaic is split across servers) and prints the
// outcome as JSON: the worst server's outcome at the top (a single server's, as before), every
// server's under "servers", and under "missing" those with no final status by the time-out.
// With --dry-run it previews the job on a mosaic file instead (no DDS, nothing written): the
// tiles it would change and what it would fold and refuse, judged by the map server's policy.
#include <spdlog/fmt/ranges.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <thread>

#include "commands.h"
#include "map_server/map_server_config.h"
#include "mosaic_upkeep/remap_job.h"
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
  bool dry_run = false;
  std::string mosaic;         // with dry_run: the mosaic file
  std::string server_config;  // with dry_run: the map server's configuration (its policy)
};

// The job previewed on the file (mosaic_upkeep::RemapRequest::dry_run).
Status RunRemapPreview(const RemapArgs& a) {
  if (a.mosaic.empty()) return InvalidInput("--dry-run needs --mosaic FILE (the map server's)");
  mosaic_upkeep::RemapPolicy policy;
  if (!a.server_config.empty()) {
    Result<map_server::MapServerConfig> config = map_server::LoadMapServerConfig(a.server_config);
    if (!config.ok()) return config.status();
    policy = config->remap_policy;
  }
  Result<mosaic_upkeep::RemapStores> stores =
      mosaic_upkeep::OpenRemapStores(a.mosaic, mosaic::OpenMode::kReadOnly);
  if (!stores.ok()) return stores.status();
  mosaic_upkeep::RemapRequest request{
      {a.region[0], a.region[1], a.region[2], a.region[3]},
      a.mode == "replace" ? mosaic_upkeep::RemapMode::kReplace : mosaic_upkeep::RemapMode::kBlend,
      policy};
  request.dry_run = true;
  Result<mosaic_upkeep::RemapResult> r =
      mosaic_upkeep::RunRemap(*stores->tiles, *stores->patches, *stores->standing, request);
  if (!r.ok()) return r.status();
  nlohmann::json tiles = nlohmann::json::array();
  for (const mosaic::TileKey& key : r->changed_tiles) tiles.push_back(mosaic::ToString(key));
  const nlohmann::json out = {{"state", "preview"},
                              {"version", r->new_version},
                              {"tiles_changed", r->changed_tiles.size()},
                              {"tiles", tiles},
                              {"patches_folded", r->patches_folded},
                              {"patches_rejected", r->patches_rejected},
                              {"patches_held", r->patches_held},
                              {"would_quarantine", r->newly_quarantined},
                              {"message", mosaic_upkeep::RemapSummary(*r)}};
  std::cout << out.dump(2) << "\n";
  return Status::Ok();
}

using Clock = std::chrono::steady_clock;

// The map servers the command runs on: those announcing the mosaic (MosaicInfo; any mosaic
// without --mosaic-id, or when none announces it: each of them then says it does not know that
// mosaic, as a single server always did). Waits until at least one announces and as many read our
// commands, and the announced set has then held for a moment (servers are discovered within moments
// of each other), bounded by `deadline`.
Result<std::vector<std::string>> WaitForServers(transport::RemapClient* client, const RemapArgs& a,
                                                Clock::time_point deadline) {
  constexpr auto kSettle = std::chrono::milliseconds(700);
  std::vector<std::string> servers;
  auto steady_since = Clock::now();
  for (;;) {
    std::vector<std::string> now = client->ServersOf(a.mosaic_id);
    if (now.empty()) now = client->ServersOf("");  // they will reject an unknown mosaic id
    if (now != servers) {
      servers = std::move(now);
      steady_since = Clock::now();
    }
    const bool listening =
        !servers.empty() && client->MatchedServers() >= static_cast<int>(servers.size());
    if (listening && Clock::now() - steady_since >= kSettle) return servers;
    if (Clock::now() > deadline) {
      return Internal(servers.empty() ? "no map server on domain " + std::to_string(a.domain)
                                      : "the map servers announcing the mosaic do not all read "
                                        "remap commands");
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
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
  out.erase("phase");
  out.erase("progress");
  out.erase("t");
  return out;
}

// Sends the command once the map servers listen, then follows their statuses until each is done,
// failed or rejected, or the time-out.
Status RunRemap(const RemapArgs& a) {
  if (a.region.size() != 4) return InvalidInput("--region: give x_min,y_min,x_max,y_max");
  if (a.dry_run) return RunRemapPreview(a);
  using namespace transport;
  auto participant = Participant::Create(a.domain, {"", a.dds_config});
  if (!participant.ok()) return participant.status();
  auto client = RemapClient::Create(*participant);
  if (!client.ok()) return client.status();
  const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                           std::chrono::duration<double>(a.timeout_s));
  Result<std::vector<std::string>> servers = WaitForServers(client->get(), a, deadline);
  if (!servers.ok()) return servers.status();
  const RemapRequest request{a.region[0],         a.region[1], a.region[2], a.region[3],
                             a.mode == "replace", a.mosaic_id, "fleetctl"};
  Result<uint64_t> id = (*client)->Send(request);
  if (!id.ok()) return id.status();
  spdlog::info("remap: command {} sent to {} map server(s): {}", *id, servers->size(),
               fmt::join(*servers, ", "));
  std::map<std::string, RemapProgress> finals;  // by server id, of the expected servers
  const auto expected = [&](const std::string& server) {
    return std::find(servers->begin(), servers->end(), server) != servers->end();
  };
  while (finals.size() < servers->size() && Clock::now() < deadline) {
    Result<std::vector<RemapProgress>> statuses = (*client)->TakeStatuses();
    if (!statuses.ok()) return statuses.status();
    for (const RemapProgress& s : *statuses) {
      if (s.command_id != *id || !expected(s.server_id)) continue;  // another job, or mosaic
      spdlog::info("remap: {} {} {} {:.0f}%", s.server_id, RemapStateName(s.state), s.phase,
                   100 * s.progress);
      if (s.final()) finals.emplace(s.server_id, s);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  std::vector<std::string> missing;
  for (const std::string& server : *servers) {
    if (!finals.count(server)) missing.push_back(server);
  }
  if (finals.empty()) {
    return Internal("remap: no map server gave a final status within " +
                    std::to_string(a.timeout_s) + " s");
  }
  const RemapProgress& worst = Worst(finals);
  nlohmann::json out = Outcome(worst);
  out["servers"] = nlohmann::json::array();
  for (const auto& [server, s] : finals) out["servers"].push_back(Outcome(s));
  out["missing"] = missing;  // servers with no final status by the time-out
  std::cout << out.dump(2) << "\n";
  if (!missing.empty()) {
    return Internal("remap: no final status within " + std::to_string(a.timeout_s) + " s from " +
                    fmt::format("{}", fmt::join(missing, ", ")) +
                    " (the servers' replicas may now differ)");
  }
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
  remap->add_option("--timeout", a->timeout_s, "Seconds to wait for the job")
      ->check(CLI::PositiveNumber);
  remap->add_flag("--dry-run", a->dry_run,
                  "Preview the job on --mosaic FILE: the tiles it would change and what it would "
                  "fold and refuse; writes nothing, needs no DDS");
  remap->add_option("--mosaic", a->mosaic, "With --dry-run: the mosaic file");
  remap->add_option("--server-config", a->server_config,
                    "With --dry-run: the map server's configuration, whose patch_admission policy "
                    "judges the patches (default: the built-in policy)");
  remap->callback([a, result] { *result = RunRemap(*a); });
}

}  // namespace fleetloc::fleetctl
