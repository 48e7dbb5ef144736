// The fleet spread over five "hosts" (network namespaces, NetnsLab) talking DDS with the shipped
// multi-host configuration (deploy/cyclonedds/multihost.xml, unicast peers, no multicast):
//   ms1 10.10.0.1   map server ms-west, owning tile columns [0, 5) of the mosaic
//   sup 10.10.0.2   fleet supervisor (HTTP API inside its host)
//   ms2 10.10.0.3   map server ms-east, owning columns [5, 10); its own replica of the mosaic
//   agv1 10.10.0.11, agv2 10.10.0.12   tracker agents driving simulated vehicles forever
// optionally with DDS Security (Mode::kSecured) or loss and delay between the hosts (kLossy).
// The mosaic is the moss photograph (1.28 m x 0.8 m, 10 x 7 tiles); the vehicles drive over the
// same floor with a new brick marking at the middle, so they also send patches. Their tile caches
// are small (2 MB), so tiles keep streaming from both servers as they cross the boundary.
#pragma once

#include <gtest/gtest.h>
#include <signal.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "cli_runner.h"
#include "map_server_fixture.h"
#include "mosaic/importer.h"
#include "netns_lab.h"
#include "sqlite_value.h"

namespace fleetloc::testing {

// `text` parsed, or null when it is not JSON (a process that did not answer or write).
inline nlohmann::json JsonOrNull(const std::string& text) {
  nlohmann::json parsed = nlohmann::json::parse(text, nullptr, false);
  return parsed.is_discarded() ? nlohmann::json() : parsed;
}

class MultiHostFleet {
 public:
  static constexpr double kBoundaryX = 0.64;  // map x of tile column 5
  static constexpr const char* kVehicles[] = {"agv-1", "agv-2"};

  enum class Mode { kPlain, kLossy, kSecured };

  // Builds the network and starts the fleet; `skip` set (and nothing started) where this machine
  // cannot have network namespaces.
  // kLossy: packet loss and delay between the hosts from the start — every frame from one host
  // to another is lost with probability 2 % and the rest arrive 20 ± 5 ms late: netem on every
  // host's link, or, on a kernel without netem (some container kernels), netns_switch in place of
  // the bridge doing the same in userspace.
  // kSecured: DDS Security, the recommended production setting — deploy/security/make_security.sh
  // makes the site's credentials over the multi-host configuration, and every process runs as
  // its own participant (server-ms-west, server-ms-east, supervisor-sup-1, vehicle-agv-1,
  // vehicle-agv-2; fleetctl as maintainer-ops-1).
  explicit MultiHostFleet(const std::string& name, Mode mode = Mode::kPlain)
      : name_(name), dir_(name), secured_(mode == Mode::kSecured) {
    auto lab = NetnsLab::Create({{"ms1", "10.10.0.1"},
                                 {"sup", "10.10.0.2"},
                                 {"ms2", "10.10.0.3"},
                                 {"agv1", "10.10.0.11"},
                                 {"agv2", "10.10.0.12"}});
    if (!lab.ok()) {
      skip = lab.status().message();
      EXPECT_EQ(lab.status().code(), StatusCode::kNotFound) << skip;
      return;
    }
    lab_ = std::move(lab).value();
    if (mode == Mode::kLossy) Impair();
    if ((secured_ && !MakeCredentials()) || !MakeFloors()) {
      skip = "the fleet's files could not be made (see the failures above)";
      return;  // nothing started: the test stops at its skip check, failed
    }
    for (const char* process : {"ms-west", "ms-east", "sup", "agv-1", "agv-2"}) Start(process);
  }

  // A failed test keeps the processes' logs, configurations and agent summaries in
  // build/test-artifacts/<name>/ (any test does with FLEETLOC_KEEP_TEST_LOGS=1).
  ~MultiHostFleet() {
    processes_.clear();
    if (!lab_ || !(::testing::Test::HasFailure() || std::getenv("FLEETLOC_KEEP_TEST_LOGS"))) return;
    const std::filesystem::path keep =
        std::filesystem::path(FLEETLOC_BINARY_DIR "/test-artifacts") / name_;
    std::filesystem::create_directories(keep);
    for (const auto& entry : std::filesystem::directory_iterator(dir_.path())) {
      if (entry.path().extension() == ".log" || entry.path().extension() == ".json") {
        std::filesystem::copy_file(entry.path(), keep / entry.path().filename(),
                                   std::filesystem::copy_options::overwrite_existing);
      }
    }
    std::printf("logs kept in %s\n", keep.c_str());
  }

  std::string skip;
  std::string impairment;  // what `lossy` put between the hosts
  bool switched = false;   // kLossy on a kernel without netem: netns_switch impairs the links

  // Starts (or restarts) one of the fleet's processes.
  void Start(const std::string& name) {
    const std::string log = dir_ / (name + "_" + std::to_string(++starts_[name]) + ".log");
    const std::vector<std::string> dds{"--dds-config", DdsConfig(name)};
    std::vector<std::string> args;
    std::string host, program;
    if (name == "ms-west" || name == "ms-east") {
      host = name == "ms-west" ? "ms1" : "ms2";
      program = "map_server";
      args = {"--config", ServerConfig(name)};
    } else if (name == "sup") {
      host = "sup";
      program = "fleet_supervisor";
      args = {"--http-port", "8080", "--history", dir_ / "history.db", "--token-file", TokenFile()};
    } else {
      host = name == "agv-1" ? "agv1" : "agv2";
      program = "tracker_agent";
      args = {"--config",   AgentConfig(name), "--outbox",
              Outbox(name), "--summary",       Summary(name, starts_[name])};
    }
    args.insert(args.end(), dds.begin(), dds.end());
    processes_.erase(name);
    processes_.emplace(name, lab_->Start(host, program, args, log));
  }
  // Stops one with `signal`; its exit status.
  int Stop(const std::string& name, int signal) {
    const int status = processes_.at(name).Stop(signal);
    processes_.erase(name);
    return status;
  }
  // Every process still running stops cleanly on SIGTERM (agents drain their outboxes first).
  void StopAll() {
    for (auto& [name, process] : processes_)
      EXPECT_EQ(process.Stop(SIGTERM, std::chrono::seconds(30)), 0) << name;
    processes_.clear();
  }

  NetnsLab& lab() { return *lab_; }
  // IP fragments the hosts created: DDS messages larger than the link MTU (the shipped
  // configuration keeps them below it, so one lost packet costs one DDS fragment, not a sample).
  long long IpFragmentsCreated() const {
    long long total = 0;
    for (const char* host : {"ms1", "sup", "ms2", "agv1", "agv2"})
      total += lab_->IpCounter(host, "FragCreates");
    return total;
  }
  // The summary agent `vehicle` wrote when its `start`-th run stopped (null before).
  nlohmann::json AgentSummary(const std::string& vehicle, int start = 1) const {
    const std::string text = ReadWhole(Summary(vehicle, start));
    return JsonOrNull(text);
  }
  std::string Outbox(const std::string& vehicle) const {
    return dir_ / ("outbox-" + vehicle + ".db");
  }
  std::string Mosaic(const std::string& server) const { return dir_ / (server + ".db"); }
  const ScratchDir& dir() const { return dir_; }
  // What netns_switch did (kLossy without netem): frames forwarded, lost, their mean delay...;
  // null when it did not run.
  nlohmann::json SwitchCounts() const {
    const std::string text = ReadWhole(SwitchStats());
    return JsonOrNull(text);
  }

  // GET `path` from the supervisor's API (inside its host); null when it does not answer.
  nlohmann::json Api(const std::string& path) const {
    const std::string body =
        lab_->Capture("sup", "curl -sf --max-time 5 'http://127.0.0.1:8080" + path + "'");
    return JsonOrNull(body);
  }
  // `fleetctl status --json` run on the supervisor's host (secured: as maintainer ops-1): vehicles,
  // services with counters, mosaics.
  nlohmann::json Status() const {
    const std::string body = lab_->Capture(
        "sup",
        std::string(FLEETLOC_BINARY_DIR "/bin/fleetctl status --json --wait 3 --dds-config ") +
            DdsConfig("ops-1"));
    return JsonOrNull(body);
  }
  // The supervisor sees both vehicles tracking and every map server reachable from both.
  bool AllTracking() const {
    const nlohmann::json fleet = Api("/api/fleet");
    if (!fleet.is_object() || fleet["summary"].value("tracking", 0) < 2) return false;
    for (const nlohmann::json& v : fleet["vehicles"]) {
      if (!v["health"].is_object() || !v["health"].value("map_server_reachable", false))
        return false;
    }
    return true;
  }
  // The lock states and x positions the supervisor recorded for `vehicle` since `from` (its clock).
  std::pair<std::vector<std::string>, std::vector<double>> Trace(const std::string& vehicle,
                                                                 double from) const {
    const nlohmann::json h =
        Api("/api/vehicles/" + vehicle + "/history?max_points=5000&from=" + std::to_string(from));
    if (!h.is_object()) return {};
    return {h["poses"]["lock"].get<std::vector<std::string>>(),
            h["poses"]["x"].get<std::vector<double>>()};
  }
  long long StoredPatches(const std::string& server) const {
    return SqliteValue(Mosaic(server), "SELECT COUNT(*) FROM patches");
  }
  // How many of the patches `vehicle` queued were acknowledged but are not stored by `server`.
  long long AcknowledgedButMissing(const std::string& vehicle, const std::string& server) const {
    return testing::AcknowledgedButMissing(Outbox(vehicle), vehicle, Mosaic(server));
  }
  long long Queued(const std::string& vehicle) const { return QueuedPatches(Outbox(vehicle)); }

 private:
  bool MakeFloors() {
    const cv::Mat floor = cv::imread(FLEETLOC_SOURCE_DIR "/deploy/demo/floors/moss_2560x1600.jpg",
                                     cv::IMREAD_GRAYSCALE);
    EXPECT_TRUE(cv::imwrite(dir_ / "floor.png", floor));
    mosaic::ImportOptions options;
    options.resolution_m = 0.0005;
    auto imported = mosaic::ImportImage(dir_ / "floor.png", options, Mosaic("ms-west"));
    if (!imported.ok()) {
      ADD_FAILURE() << imported.status().message();
      return false;
    }
    std::filesystem::copy_file(Mosaic("ms-west"), Mosaic("ms-east"));
    cv::Mat changed = floor.clone();
    const cv::Mat brick =
        cv::imread(FLEETLOC_SOURCE_DIR "/tests/data/brick.png", cv::IMREAD_GRAYSCALE);
    brick(cv::Rect(0, 0, 256, 256)).copyTo(changed(cv::Rect(1152, 672, 256, 256)));
    EXPECT_TRUE(cv::imwrite(dir_ / "changed_floor.png", changed));
    return true;
  }
  void Impair() {
    if (lab_->NetemAvailable()) {
      for (const char* host : {"ms1", "sup", "ms2", "agv1", "agv2"}) {
        EXPECT_TRUE(lab_->Netem(host, "delay 20ms 5ms loss 2%")) << host;
      }
      impairment = "netem: 2 % loss, 20 +- 5 ms delay on every link";
      return;
    }
    switched = lab_->ImpairWithSwitch(20, 5, 0.02, SwitchStats(), dir_ / "netns_switch.log");
    EXPECT_TRUE(switched) << "netns_switch did not start";
    impairment = "no netem in this kernel; netns_switch: 2 % loss, 20 +- 5 ms delay between hosts";
  }
  bool MakeCredentials() {
    const std::string command =
        std::string(FLEETLOC_SOURCE_DIR "/deploy/security/make_security.sh") + " --out " +
        (dir_ / "security") + " --base-config " + dds_config_ +
        " --servers ms-west,ms-east --supervisors sup-1 --vehicles agv-1,agv-2"
        " --maintainers ops-1 >" +
        (dir_ / "make_security.log") + " 2>&1";
    if (std::system(command.c_str()) == 0) return true;
    ADD_FAILURE() << "make_security.sh failed: " << ReadWhole(dir_ / "make_security.log");
    return false;
  }
  // The Cyclone configuration process `name` runs with.
  std::string DdsConfig(const std::string& name) const {
    if (!secured_) return dds_config_;
    const std::string participant = name.rfind("ms-", 0) == 0 ? "server-" + name
                                    : name == "sup"           ? "supervisor-sup-1"
                                    : name == "ops-1"         ? "maintainer-ops-1"
                                                              : "vehicle-" + name;
    return dir_ / ("security/participants/" + participant + "/cyclonedds.xml");
  }
  std::string Summary(const std::string& vehicle, int start) const {
    return dir_ / (vehicle + "_summary_" + std::to_string(start) + ".json");
  }
  std::string SwitchStats() const { return dir_ / "netns_switch.json"; }
  std::string ServerConfig(const std::string& id) const {
    const bool west = id == "ms-west";
    const nlohmann::json config{{"server_id", id},
                                {"mosaic", Mosaic(id)},
                                {"owned_tiles",
                                 {{"col_begin", west ? 0 : 5},
                                  {"col_end", west ? 5 : 10},
                                  {"row_begin", 0},
                                  {"row_end", 7}}}};
    return Write(id + ".json", config);
  }
  std::string AgentConfig(const std::string& id) const {
    const nlohmann::json config{{"vehicle_id", id},
                                {"source", "sim"},
                                {"sim_floor", dir_ / "changed_floor.png"},
                                {"sim_start_fraction", id == "agv-1" ? 0.0 : 0.5},
                                {"sim_seed", id == "agv-1" ? 1 : 2},
                                {"tile_cache_mb", 2}};
    return Write(id + ".json", config);
  }
  std::string TokenFile() const {
    std::ofstream(dir_ / "token") << "multihost-test-token\n";
    std::filesystem::permissions(
        dir_ / "token", std::filesystem::perms::owner_read | std::filesystem::perms::owner_write);
    return dir_ / "token";
  }
  std::string Write(const std::string& name, const nlohmann::json& config) const {
    std::ofstream(dir_ / name) << config.dump(2);
    return dir_ / name;
  }

  std::string name_;
  ScratchDir dir_;
  bool secured_;
  const std::string dds_config_ = FLEETLOC_SOURCE_DIR "/deploy/cyclonedds/multihost.xml";
  std::unique_ptr<NetnsLab> lab_;                           // declared before the processes:
  std::map<std::string, runtime::ChildProcess> processes_;  // they stop before the network goes
  std::map<std::string, int> starts_;
};

}  // namespace fleetloc::testing
