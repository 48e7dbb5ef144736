// DDS Security (docs/security.md) with real processes: credentials made at test time by
// deploy/security/make_security.sh; a map server, a fleet supervisor, a tracker agent and
// security_probe participants run on their own secured configurations, and this process is the
// maintainer `alice`. Each refusal of the requirement is shown: a vehicle cannot command a
// re-map (a maintainer can), cannot write in another vehicle's partition nor pass off another
// vehicle's id in its own, and outsiders (another CA, no security, forged permissions) are never
// matched; a secured fleet tracks.
// Eigen (through pose_messages.h) before httplib: <resolv.h> defines a macro `_res` that breaks
// Eigen's headers when included first.
// clang-format off
#include "transport/pose_messages.h"
// clang-format on

#include <gtest/gtest.h>
#include <httplib.h>
#include <signal.h>

#include <future>
#include <map>
#include <memory>
#include <opencv2/imgcodecs.hpp>
#include <set>

#include "cli_runner.h"
#include "map_server_fixture.h"
#include "supervisor_fixture.h"
#include "transport/vehicle_streams.h"

namespace fleetloc {
namespace {

// Domains 111-114 (110 is vehicle_streams_test's); one per test, all in the governance.
constexpr uint32_t kRemapDomain = 111, kPartitionDomain = 112, kOutsiderDomain = 113,
                   kFleetDomain = 114;

// The site's credentials, an outsider site's (its own CAs) and a forged vehicle configuration,
// made once for this test binary.
class Credentials {
 public:
  static const Credentials& Get() {
    static const Credentials credentials;
    return credentials;
  }
  // The secured Cyclone configuration of `participant` (e.g. "vehicle-agv-1").
  std::string Config(const std::string& participant) const {
    return (dir_.path() / "site/participants" / participant / "cyclonedds.xml").string();
  }
  std::string OutsiderConfig() const {
    return (dir_.path() / "outsider/participants/vehicle-agv-1/cyclonedds.xml").string();
  }
  std::string ForgedConfig() const { return (dir_.path() / "forged/cyclonedds.xml").string(); }

 private:
  Credentials() : dir_("security_credentials") {
    const std::string script = FLEETLOC_SOURCE_DIR "/deploy/security/make_security.sh";
    const std::string site = (dir_.path() / "site").string();
    const std::string outsider = (dir_.path() / "outsider").string();
    const std::string log = " >>" + (dir_.path() / "make.log").string() + " 2>&1";
    Run(script + " --out " + site + " --domain 111-114 --maintainers alice --vehicles agv-1,agv-2" +
        " --servers map-1 --supervisors sup-1" + log);
    Run(script + " --out " + outsider + " --domain 111-114 --vehicles agv-1" + log);
    Run(FLEETLOC_SOURCE_DIR "/tests/security/forge_permissions.sh " + site + " vehicle-agv-1 " +
        outsider + " " + (dir_.path() / "forged").string() + log);
  }
  void Run(const std::string& command) const {
    const int status = std::system(command.c_str());
    if (status != 0) {
      ADD_FAILURE() << command << " failed:\n" << testing::ReadWhole(dir_.path() / "make.log");
      std::abort();
    }
  }
  testing::ScratchDir dir_;
};

std::vector<std::string> SecuredAs(const std::string& participant) {
  return {"--dds-config", Credentials::Get().Config(participant)};
}

// A map server (identity server-map-1) over the demo gravel floor (floor.png in `dir`) on `domain`.
class SecuredMapServer {
 public:
  SecuredMapServer(const testing::ScratchDir& dir, uint32_t domain)
      : floor_((dir.path() / "floor.png").string()) {
    const cv::Mat gray =
        cv::imread(FLEETLOC_SOURCE_DIR "/deploy/demo/floors/gravel_1024.png", cv::IMREAD_GRAYSCALE);
    EXPECT_TRUE(cv::imwrite(floor_, gray));
    mosaic::ImportOptions options;
    options.resolution_m = 0.0005;
    const std::string mosaic = (dir.path() / "floor.db").string();
    EXPECT_TRUE(mosaic::ImportImage(floor_, options, mosaic).ok());
    std::vector<std::string> args = {"--mosaic",    mosaic, "--domain", std::to_string(domain),
                                     "--server-id", "map-1"};
    for (const std::string& a : SecuredAs("server-map-1")) args.push_back(a);
    log_ = (dir.path() / "map_server.log").string();
    process_ =
        std::make_unique<runtime::ChildProcess>(testing::StartDaemon("map_server", args, log_));
  }
  ~SecuredMapServer() { EXPECT_EQ(process_->Stop(SIGTERM), 0) << log(); }
  std::string log() const { return testing::ReadWhole(log_); }
  const std::string& floor() const { return floor_; }

 private:
  std::string floor_;
  std::string log_;
  std::unique_ptr<runtime::ChildProcess> process_;
};

// This process's participant: the maintainer alice, reading the vehicles' poses (checked against
// their partitions) and every service's health.
class Maintainer {
 public:
  explicit Maintainer(uint32_t domain)
      : participant_(transport::Participant::Create(
                         domain, {"", Credentials::Get().Config("maintainer-alice")})
                         .value()),
        pose_topic_(transport::Topic<fleetloc_VehiclePose>::Create(participant_,
                                                                   transport::topics::kVehiclePose)
                        .value()),
        health_topic_(transport::Topic<fleetloc_ServiceHealth>::Create(
                          participant_, transport::topics::kServiceHealth)
                          .value()),
        poses_(transport::VehicleStreamReader<fleetloc_VehiclePose>::Create(
                   participant_, pose_topic_, transport::Qos().Reliable().KeepAll())
                   .value()),
        services_(transport::Reader<fleetloc_ServiceHealth>::Create(
                      participant_.get(), health_topic_, transport::PeriodicStateQos(3, 5))
                      .value()) {}

  // Takes the poses received so far: their vehicle ids and lock states.
  void TakePoses() {
    (void)poses_.TakeAll([&](const fleetloc_VehiclePose& p, const dds_sample_info_t&) {
      vehicles_.insert(transport::GetBounded(p.vehicle_id));
      if (p.lock_state == fleetloc_LOCK_TRACKING)
        tracking_.insert(transport::GetBounded(p.vehicle_id));
    });
  }
  // The newest value of counter `name` in the ServiceHealth of `service_id` (0 before a report).
  uint64_t Counter(const std::string& service_id, const std::string& name) {
    (void)services_.TakeAll([&](const fleetloc_ServiceHealth& h, const dds_sample_info_t&) {
      for (uint32_t i = 0; i < h.counters._length; ++i) {
        counters_[{transport::GetBounded(h.service_id),
                   transport::GetBounded(h.counters._buffer[i].name)}] =
            h.counters._buffer[i].value;
      }
    });
    return counters_[{service_id, name}];
  }
  const std::set<std::string>& vehicles() const { return vehicles_; }
  const std::set<std::string>& tracking() const { return tracking_; }
  uint64_t rejected_poses() const { return poses_.rejected(); }

 private:
  transport::Participant participant_;
  transport::Topic<fleetloc_VehiclePose> pose_topic_;
  transport::Topic<fleetloc_ServiceHealth> health_topic_;
  transport::VehicleStreamReader<fleetloc_VehiclePose> poses_;
  transport::Reader<fleetloc_ServiceHealth> services_;
  std::set<std::string> vehicles_, tracking_;
  std::map<std::pair<std::string, std::string>, uint64_t> counters_;
};

// Runs security_probe with `args` to its end; exit status and output.
testing::CommandResult Probe(const testing::ScratchDir& dir, const std::string& name,
                             const std::vector<std::string>& args) {
  const std::string log = (dir.path() / (name + ".log")).string();
  auto child = runtime::ChildProcess::Start(FLEETLOC_BINARY_DIR "/bin/security_probe", args, log);
  EXPECT_TRUE(child.ok()) << child.status().message();
  testing::CommandResult r;
  if (child.ok()) r.exit_code = child->Wait(std::chrono::seconds(60));
  r.out = testing::ReadWhole(log);
  return r;
}

// Runs the probes (name, args) at once to their end while `alice` takes poses; their results.
std::vector<testing::CommandResult> ProbesWhileTaking(
    const testing::ScratchDir& dir, Maintainer& alice,
    const std::vector<std::pair<std::string, std::vector<std::string>>>& probes) {
  std::vector<std::future<testing::CommandResult>> running;
  for (const auto& [name, args] : probes) {
    running.push_back(std::async(
        std::launch::async, [&dir, name = name, args = args] { return Probe(dir, name, args); }));
  }
  std::vector<testing::CommandResult> results;
  for (auto& r : running) {
    while (r.wait_for(std::chrono::milliseconds(50)) != std::future_status::ready)
      alice.TakePoses();
    results.push_back(r.get());
  }
  alice.TakePoses();
  return results;
}

// Probe arguments: participant `config` writing vehicle `id`'s streams in `partition_of`'s
// partition.
std::vector<std::string> Streams(uint32_t domain, const std::string& config,
                                 const std::string& partition_of, const std::string& id,
                                 double seconds) {
  std::vector<std::string> args = {"--domain",   std::to_string(domain), "--partition-of",
                                   partition_of, "--vehicle-id",         id,
                                   "--seconds",  std::to_string(seconds)};
  if (!config.empty()) args.insert(args.end(), {"--dds-config", config});
  return args;
}

constexpr const char* kRefused = "Not Allowed By Security";

TEST(Security, OnlyAMaintainerCanCommandARemap) {
  testing::ScratchDir dir("security_remap");
  SecuredMapServer server(dir, kRemapDomain);
  const std::string region =
      " --domain " + std::to_string(kRemapDomain) + " --region 0.1,0.1,0.2,0.2 --timeout 60";
  const auto vehicle = testing::RunFleetctl("remap --dds-config " +
                                            Credentials::Get().Config("vehicle-agv-1") + region);
  EXPECT_NE(vehicle.exit_code, 0);
  EXPECT_NE(vehicle.err.find(kRefused), std::string::npos) << vehicle.err;
  const auto probe = Probe(dir, "vehicle_remap",
                           {"--domain", std::to_string(kRemapDomain), "--remap", "--dds-config",
                            Credentials::Get().Config("vehicle-agv-1")});
  EXPECT_EQ(probe.exit_code, 3) << probe.out;
  EXPECT_NE(probe.out.find(kRefused), std::string::npos) << probe.out;
  // The maintainer's command reaches the map server, which runs it and reports its status.
  const auto maintainer = testing::RunFleetctl(
      "remap --dds-config " + Credentials::Get().Config("maintainer-alice") + region);
  EXPECT_EQ(maintainer.exit_code, 0) << maintainer.out << maintainer.err << server.log();
  EXPECT_NE(maintainer.out.find("done"), std::string::npos) << maintainer.out << maintainer.err;
}

TEST(Security, AVehicleWritesOnlyItsOwnPartitionAndOnlyItsOwnId) {
  testing::ScratchDir dir("security_partition");
  SecuredMapServer server(dir, kPartitionDomain);
  testing::SupervisorProcess supervisor(dir.path(), kPartitionDomain, "tok-sec-tok-sec-0",
                                        SecuredAs("supervisor-sup-1"));
  Maintainer alice(kPartitionDomain);
  const std::string agv1 = Credentials::Get().Config("vehicle-agv-1");
  // Writers in agv-2's partition: refused to agv-1 by its own permissions.
  const auto other =
      Probe(dir, "agv1_as_agv2", Streams(kPartitionDomain, agv1, "agv-2", "agv-2", 0.1));
  EXPECT_EQ(other.exit_code, 3) << other.out;
  for (const char* topic : {"vehicle_pose", "vehicle_health", "patch_observation"}) {
    EXPECT_NE(other.out.find(std::string(topic) + " writer: DDS writer of fleetloc/" + topic +
                             ": " + kRefused),
              std::string::npos)
        << other.out;
  }
  // Its own partition: its own id is delivered; agv-2's id there is rejected and counted by the
  // map server (patches), the supervisor (poses, health) and this reader.
  const auto results =
      ProbesWhileTaking(dir, alice,
                        {{"agv1_own", Streams(kPartitionDomain, agv1, "agv-1", "agv-1", 4)},
                         {"agv1_forged_id", Streams(kPartitionDomain, agv1, "agv-1", "agv-2", 4)}});
  EXPECT_EQ(results[0].exit_code, 0) << results[0].out;
  EXPECT_EQ(results[1].exit_code, 0) << results[1].out;
  EXPECT_TRUE(testing::Eventually(
      [&] {
        alice.TakePoses();
        return alice.Counter("map-1", "rejected_vehicle_partition") > 0 &&
               alice.Counter("sup-1", "rejected_samples") > 0;
      },
      15))
      << server.log() << supervisor.log();
  EXPECT_EQ(alice.vehicles(), std::set<std::string>{"agv-1"});
  EXPECT_GT(alice.rejected_poses(), 0u);
  httplib::Client http("127.0.0.1", supervisor.port());
  auto listed = http.Get("/api/vehicles/agv-2");
  ASSERT_TRUE(listed);
  EXPECT_EQ(listed->status, 404) << "the supervisor took agv-2's forged samples: " << listed->body;
}

TEST(Security, OutsidersAreNeverMatched) {
  testing::ScratchDir dir("security_outsiders");
  SecuredMapServer server(dir, kOutsiderDomain);
  Maintainer alice(kOutsiderDomain);
  const Credentials& c = Credentials::Get();
  // All at once: a legitimate vehicle, a vehicle of another CA, a participant without security,
  // and agv-1's real identity with forged permissions writing in agv-9's partition.
  const auto results = ProbesWhileTaking(
      dir, alice,
      {{"legit", Streams(kOutsiderDomain, c.Config("vehicle-agv-2"), "agv-2", "agv-2", 8)},
       {"foreign_ca", Streams(kOutsiderDomain, c.OutsiderConfig(), "agv-1", "agv-1", 8)},
       {"no_security", Streams(kOutsiderDomain, "", "agv-3", "agv-3", 8)},
       {"forged_permissions", Streams(kOutsiderDomain, c.ForgedConfig(), "agv-9", "agv-9", 8)}});
  EXPECT_NE(results[0].out.find("matched pose readers: 1"), std::string::npos) << results[0].out;
  for (int i = 1; i < 4; ++i) {
    EXPECT_EQ(results[i].exit_code, 0) << results[i].out;  // their own checks let them write ...
    EXPECT_NE(results[i].out.find("matched pose readers: 0"), std::string::npos)
        << results[i].out;  // ... to nobody
  }
  EXPECT_EQ(alice.vehicles(), std::set<std::string>{"agv-2"});
}

TEST(Security, ASecuredFleetTracks) {
  testing::ScratchDir dir("security_fleet");
  SecuredMapServer server(dir, kFleetDomain);
  testing::SupervisorProcess supervisor(dir.path(), kFleetDomain, "tok-sec-tok-sec-0",
                                        SecuredAs("supervisor-sup-1"));
  std::vector<std::string> args = {
      "--sim-floor",  server.floor(), "--domain", std::to_string(kFleetDomain),
      "--vehicle-id", "agv-1",        "--outbox", (dir.path() / "outbox.db").string()};
  for (const std::string& a : SecuredAs("vehicle-agv-1")) args.push_back(a);
  runtime::ChildProcess agent =
      testing::StartDaemon("tracker_agent", args, (dir.path() / "agent.log").string());
  Maintainer alice(kFleetDomain);
  httplib::Client http("127.0.0.1", supervisor.port());
  std::string seen;
  EXPECT_TRUE(testing::Eventually(
      [&] {
        alice.TakePoses();
        auto r = http.Get("/api/vehicles/agv-1");
        if (r && r->status == 200) seen = r->body;
        return alice.tracking().count("agv-1") && seen.find("\"tracking\"") != std::string::npos;
      },
      60))
      << "supervisor: " << seen << "\nagent log:\n"
      << testing::ReadWhole(dir.path() / "agent.log");
  EXPECT_EQ(alice.rejected_poses(), 0u);
  EXPECT_EQ(agent.Stop(SIGTERM), 0);
}

}  // namespace
}  // namespace fleetloc
