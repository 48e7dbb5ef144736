// fleetctl status: listens to the running fleet over DDS for a moment (VehiclePose, VehicleHealth,
// ServiceHealth, MosaicInfo) and prints a fleet summary — a table, or JSON with --json (the same
// vehicle fields as the supervisor's /api/fleet). With --supervisor URL it prints the supervisor's
// view instead (GET /api/fleet), which includes vehicles that stopped talking, shown STALE.
// Eigen (through the transport headers) before httplib: see guarded_server.h.
#include "fleet_link/fleet_listener.h"
#include "fleet_link/fleet_view.h"

// Eigen (through the transport headers) before httplib: <resolv.h>, which httplib includes,
// defines `_res`, a name Eigen's headers use.
// clang-format off
#include <Eigen/Core>
#include <httplib.h>
// clang-format on
#include <spdlog/spdlog.h>

#include <chrono>
#include <cstdio>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <thread>

#include "commands.h"
#include "io/json_fields.h"
#include "served_mosaics.h"
#include "transport/mosaic_messages.h"
#include "transport/topic_names.h"
#include "transport/wire_util.h"

namespace fleetloc::fleetctl {
namespace {

struct StatusArgs {
  int domain = 0;
  std::string dds_config;
  double wait_s = 2.0;
  bool json = false;
  std::string supervisor;  // base URL of a fleet supervisor's HTTP API; empty: listen to DDS
};

double Now() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

void PrintTable(const nlohmann::json& out) {
  const nlohmann::json& s = out["summary"];
  const std::string where = out.contains("supervisor")
                                ? "from supervisor " + out["supervisor"].get<std::string>()
                                : "on domain " + std::to_string(out["domain"].get<int>());
  std::printf(
      "fleet %s: %d vehicles (%d tracking, %d coasting, %d lost, %d relocalized, %d stale)\n",
      where.c_str(), s["vehicles"].get<int>(), s["tracking"].get<int>(), s["coasting"].get<int>(),
      s["lost"].get<int>(), s["relocalized"].get<int>(), s["silent"].get<int>());
  for (const nlohmann::json& m : out["mosaics"]) {
    std::printf("mosaic %s version %lld from %s\n", m["mosaic_id"].get<std::string>().c_str(),
                m["version"].get<long long>(), m["server_id"].get<std::string>().c_str());
  }
  for (const nlohmann::json& sv : out["services"]) {
    std::printf("service %-11s %-16s %s\n", sv["id"].get<std::string>().c_str(),
                sv["kind"].get<std::string>().c_str(), sv["level"].get<std::string>().c_str());
  }
  std::printf("%-11s %-11s %10s %10s %8s %7s %8s %-6s %s\n", "vehicle", "lock", "x m", "y m",
              "theta", "sigma mm", "p95 ms", "health", "issues");
  for (const nlohmann::json& v : out["vehicles"]) {
    const nlohmann::json& p = v["pose"];
    const nlohmann::json& h = v["health"];
    std::string issues;
    if (!h.is_null()) {
      for (const auto& issue : h["issues"])
        issues += (issues.empty() ? "" : ",") + issue.get<std::string>();
    }
    const std::string lock = v.value("silent", false) ? "STALE"
                             : p.is_null()            ? "-"
                                                      : p["lock"].get<std::string>();
    std::printf("%-11s %-11s %10.4f %10.4f %8.3f %7.2f %8.2f %-6s %s\n",
                v["id"].get<std::string>().c_str(), lock.c_str(),
                p.is_null() ? 0.0 : p["x"].get<double>(), p.is_null() ? 0.0 : p["y"].get<double>(),
                p.is_null() ? 0.0 : p["theta"].get<double>(),
                p.is_null() ? 0.0 : p["deviation_m"].get<double>() * 1e3 / 3,
                h.is_null() ? 0.0 : h["cycle_ms"][1].get<double>(),
                h.is_null() ? "-" : h["level"].get<std::string>().c_str(), issues.c_str());
  }
}

// The supervisor's /api/fleet as the status JSON. InvalidInput for a malformed URL; Internal when
// the supervisor does not answer or answers with an error.
Result<nlohmann::json> SupervisorStatus(const std::string& url) {
  if (url.rfind("http://", 0) != 0 && url.rfind("https://", 0) != 0) {
    return InvalidInput("--supervisor " + url + ": not an http:// or https:// URL");
  }
  httplib::Client client(url);
  if (!client.is_valid()) return InvalidInput("--supervisor " + url + ": not a usable URL");
  client.set_connection_timeout(5);
  client.set_read_timeout(10);
  httplib::Result r = client.Get("/api/fleet");
  if (!r)
    return Internal("supervisor " + url + " did not answer: " + httplib::to_string(r.error()));
  nlohmann::json body = nlohmann::json::parse(r->body, nullptr, false);
  if (r->status != 200 || !body.is_object() || !body.contains("summary") ||
      !body.contains("vehicles")) {
    return Internal("supervisor " + url + " answered GET /api/fleet with HTTP " +
                    std::to_string(r->status));
  }
  return nlohmann::json{{"supervisor", url},
                        {"summary", body["summary"]},
                        {"vehicles", body["vehicles"]},
                        {"services", body.value("services", nlohmann::json::array())},
                        {"mosaics", nlohmann::json::array()}};
}

void Print(const StatusArgs& a, const nlohmann::json& out) {
  if (a.json) {
    std::cout << io::DumpJson(out, 2) << "\n";
  } else {
    PrintTable(out);
  }
}

Status RunStatus(const StatusArgs& a) {
  using namespace transport;
  if (!a.supervisor.empty()) {
    Result<nlohmann::json> out = SupervisorStatus(a.supervisor);
    if (!out.ok()) return out.status();
    Print(a, *out);
    return Status::Ok();
  }
  auto participant = Participant::Create(a.domain, {"", a.dds_config});
  if (!participant.ok()) return participant.status();
  auto listener = fleet_link::FleetListener::Create(*participant);
  if (!listener.ok()) return listener.status();
  auto info_topic = Topic<fleetloc_MosaicInfo>::Create(*participant, topics::kMosaicInfo);
  if (!info_topic.ok()) return info_topic.status();
  auto infos =
      Reader<fleetloc_MosaicInfo>::Create(participant->get(), *info_topic, DurableStateQos());
  if (!infos.ok()) return infos.status();
  fleet::FleetState fleet({}, {});
  std::map<std::string, std::pair<fleet_link::ServiceReport, double>> services;
  std::map<std::string, nlohmann::json> mosaics;
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(a.wait_s);
  do {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    fleet_link::Received in;
    FLEETLOC_RETURN_IF_ERROR((*listener)->Take(&in));
    const double now = Now();
    for (const auto& [id, pose] : in.poses) fleet.OnPose(id, pose, now);
    for (const auto& [id, health] : in.health) fleet.OnHealth(id, health, now);
    for (const auto& s : in.services) services[s.service_id] = {s, now};
    for (const std::string& rejected : in.rejections) spdlog::warn("ignored: {}", rejected);
    (void)infos->TakeAll([&](const fleetloc_MosaicInfo& info, const dds_sample_info_t&) {
      mosaics[GetBounded(info.server_id)] = MosaicInfoJson(info);
    });
  } while (std::chrono::steady_clock::now() < end);
  (void)fleet.Evaluate(Now());  // vehicles heard at the start but not since are STALE (silent_s)
  nlohmann::json out = {{"domain", a.domain},
                        {"summary", fleet_link::SummaryJson(fleet.Summary())},
                        {"vehicles", nlohmann::json::array()},
                        {"services", nlohmann::json::array()},
                        {"mosaics", nlohmann::json::array()}};
  fleet.ForEach([&](const fleet::VehicleState& v) {
    out["vehicles"].push_back(fleet_link::VehicleJson(v, fleet.Silent(v.id), false));
  });
  for (const auto& [id, entry] : services) {
    out["services"].push_back({{"id", id},
                               {"kind", entry.first.kind},
                               {"level", fleet::HealthLevelName(entry.first.level)},
                               {"counters", entry.first.counters}});
  }
  for (const auto& [id, m] : mosaics) out["mosaics"].push_back(m);
  Print(a, out);
  return Status::Ok();
}

}  // namespace

void RegisterStatusCommand(CLI::App& app, Status* result) {
  auto a = std::make_shared<StatusArgs>();
  CLI::App* status =
      app.add_subcommand("status", "Fleet summary from the running fleet (over DDS)");
  status->option_defaults()->always_capture_default();
  status->add_option("--domain", a->domain, "DDS domain")->check(CLI::Range(0, 232));
  status->add_option("--dds-config", a->dds_config, "Cyclone DDS XML (default: built-in loopback)");
  status->add_option("--wait", a->wait_s, "Seconds to listen before printing")
      ->check(CLI::Range(0.1, 600.0));
  status->add_flag("--json", a->json, "Print JSON instead of a table");
  status->add_option(
      "--supervisor", a->supervisor,
      "Ask this fleet supervisor (e.g. http://127.0.0.1:8080) instead of listening to DDS: "
      "every vehicle it knows, silent ones shown STALE");
  status->callback([a, result] { *result = RunStatus(*a); });
}

}  // namespace fleetloc::fleetctl
