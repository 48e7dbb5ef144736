// VDA 5050 visualization over MQTT from the fleet supervisor, against a real mosquitto broker the
// test starts on a free loopback port: the vehicles' visualization messages and the supervisor's
// retained connection state read back with mosquitto_sub and checked against the VDA 5050 (v2)
// schema's fields and types, and validated by an independent JSON Schema validator against
// schemas written from the standard's (tests/data/vda5050/); the broker killed and started again
// (reconnect, counted, the named health issue meanwhile, the dashboard API unaffected); wrong
// credentials refused and counted; the last will (CONNECTIONBROKEN) when the supervisor dies. Eigen
// (through the fixtures) before httplib: <resolv.h> defines a macro that breaks Eigen.
// clang-format off: these first (Eigen before httplib, whose <resolv.h> defines `_res`).
#include "fake_vehicle.h"
#include "supervisor_fixture.h"
// clang-format on

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <httplib.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>

#include "metrics/exposition.h"
#include "transport/qos.h"

namespace fleetloc {
namespace {

using nlohmann::json;
using testing::Eventually;
constexpr uint32_t kDomain = 123;

// Whether a ServiceHealth report on `participant`'s domain names `issue` (waits up to 15 s).
bool HealthNames(transport::Participant& participant, const std::string& issue) {
  auto topic = transport::Topic<fleetloc_ServiceHealth>::Create(participant,
                                                                transport::topics::kServiceHealth);
  auto reader = transport::Reader<fleetloc_ServiceHealth>::Create(
      participant.get(), *topic, transport::PeriodicStateQos(3, 5));
  if (!topic.ok() || !reader.ok()) return false;
  bool named = false;
  Eventually(
      [&] {
        (void)reader->TakeAll([&](const fleetloc_ServiceHealth& h, const dds_sample_info_t&) {
          for (uint32_t i = 0; i < h.issues._length; ++i) {
            if (transport::GetBounded(h.issues._buffer[i].name) == issue) named = true;
          }
        });
        return named;
      },
      15.0);
  return named;
}

int FreePort() {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  (void)::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr);
  socklen_t len = sizeof addr;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len);
  ::close(fd);
  return ntohs(addr.sin_port);
}

// A mosquitto broker on 127.0.0.1:port; `extra` lines go into its configuration, `client_args`
// (e.g. TLS options) into every mosquitto_sub that reads from it.
class Broker {
 public:
  Broker(const std::filesystem::path& dir, int port, const std::string& extra = "",
         std::vector<std::string> client_args = {})
      : dir_(dir), port_(port), client_args_(std::move(client_args)) {
    std::ofstream(dir / "mosquitto.conf")
        << "listener " << port << " 127.0.0.1\n"
        << "persistence false\n"
        << extra
        << (extra.find("allow_anonymous") == std::string::npos ? "allow_anonymous true\n" : "");
    Start();
  }
  void Start() {
    process_ = std::make_unique<runtime::ChildProcess>(
        std::move(runtime::ChildProcess::Start("/usr/sbin/mosquitto",
                                               {"-c", (dir_ / "mosquitto.conf").string()},
                                               (dir_ / "mosquitto.log").string())
                      .value()));
    EXPECT_TRUE(Eventually([&] { return Subscribe("$SYS/broker/version", 1, 2).size() == 1; }, 10))
        << "mosquitto did not start";
  }
  void Kill() { process_.reset(); }
  // Up to `count` messages of `topic` within `timeout_s` (each "topic payload").
  std::vector<std::string> Subscribe(const std::string& topic, int count, int timeout_s,
                                     const std::vector<std::string>& extra = {}) const {
    const std::string out = (dir_ / "sub.out").string();
    std::vector<std::string> args = {
        "-h", "127.0.0.1",           "-p", std::to_string(port_),    "-t", topic, "-v",
        "-C", std::to_string(count), "-W", std::to_string(timeout_s)};
    args.insert(args.end(), extra.begin(), extra.end());
    args.insert(args.end(), client_args_.begin(), client_args_.end());
    auto sub = runtime::ChildProcess::Start("/usr/bin/mosquitto_sub", args, out);
    if (!sub.ok()) return {};
    sub->Wait(std::chrono::seconds(timeout_s + 5));
    std::ifstream in(out);
    std::vector<std::string> lines;
    for (std::string line; std::getline(in, line);) {
      if (!line.empty()) lines.push_back(line);
    }
    return lines;
  }
  int port() const { return port_; }

 private:
  std::filesystem::path dir_;
  int port_;
  std::vector<std::string> client_args_;
  std::unique_ptr<runtime::ChildProcess> process_;
};

// A test CA and a certificate for 127.0.0.1 signed by it in `dir` (ca.crt, server.crt,
// server.key), made with openssl as a site's own PKI would; true when made.
bool MakeTlsFiles(const std::filesystem::path& dir) {
  const std::string quiet = " >/dev/null 2>&1";
  const std::string script =
      "cd '" + dir.string() + "' && " +
      "openssl req -x509 -newkey rsa:2048 -nodes -keyout ca.key -out ca.crt -days 2 "
      "-subj /CN=fleetloc-test-ca" +
      quiet + " && " +
      "openssl req -newkey rsa:2048 -nodes -keyout server.key -out server.csr -subj /CN=127.0.0.1" +
      quiet + " && printf 'subjectAltName=IP:127.0.0.1\\n' > san.ext && " +
      "openssl x509 -req -in server.csr -CA ca.crt -CAkey ca.key -CAcreateserial -out server.crt "
      "-days 2 -extfile san.ext" +
      quiet + " && chmod 644 server.key";
  return std::system(script.c_str()) == 0;
}

// The payload of a "topic payload" line, parsed.
json Payload(const std::string& line) {
  return json::parse(line.substr(line.find(' ') + 1), nullptr, false);
}

// What the VDA 5050 schema requires of the header fields; "" or the misfit.
std::string HeaderMisfit(const json& m, const std::string& serial) {
  static const std::regex iso8601(R"(\d{4}-\d{2}-\d{2}T\d{2}:\d{2}:\d{2}(\.\d+)?Z)");
  if (!m.is_object()) return "not a JSON object";
  if (!m.contains("headerId") || !m["headerId"].is_number_unsigned()) return "headerId";
  if (!m.contains("timestamp") || !m["timestamp"].is_string() ||
      !std::regex_match(m["timestamp"].get<std::string>(), iso8601))
    return "timestamp";
  if (m.value("version", "") != "2.0.0") return "version";
  if (m.value("manufacturer", "") != "acme") return "manufacturer";
  if (m.value("serialNumber", "") != serial) return "serialNumber";
  return "";
}

std::string VisualizationMisfit(const json& m, const std::string& serial) {
  if (std::string h = HeaderMisfit(m, serial); !h.empty()) return h;
  if (!m.contains("agvPosition") || !m["agvPosition"].is_object()) return "agvPosition";
  const json& a = m["agvPosition"];
  for (const char* key : {"x", "y", "theta"}) {
    if (!a.contains(key) || !a[key].is_number()) return std::string("agvPosition.") + key;
  }
  if (!a.contains("mapId") || !a["mapId"].is_string()) return "agvPosition.mapId";
  if (!a.contains("positionInitialized") || !a["positionInitialized"].is_boolean())
    return "positionInitialized";
  if (!a["mapDescription"].is_string()) return "mapDescription";
  const double score = a.value("localizationScore", -1.0);
  if (!(score >= 0 && score <= 1)) return "localizationScore";
  if (!a["deviationRange"].is_number()) return "deviationRange";
  if (m.contains("velocity")) {
    for (const char* key : {"vx", "vy", "omega"}) {
      if (!m["velocity"][key].is_number()) return std::string("velocity.") + key;
    }
  }
  return "";
}

// What an independent JSON Schema validator (Debian's python3-jsonschema, draft 2020-12) finds
// wrong with `message` against tests/data/vda5050/`schema` ("" when valid). The schemas are
// written from the standard's published ones, stricter where fleetloc promises more.
std::string SchemaMisfit(const std::filesystem::path& scratch, const std::string& schema,
                         const json& message) {
  static int serial = 0;
  const std::filesystem::path file = scratch / ("message_" + std::to_string(serial++) + ".json");
  std::ofstream(file) << message.dump();
  const std::string data = FLEETLOC_SOURCE_DIR "/tests/data/vda5050/";
  const testing::CommandResult r = testing::RunCommand("/usr/bin/python3 " + data + "validate.py " +
                                                       data + schema + " " + file.string());
  return r.exit_code == 0 ? "" : r.err + r.out;
}

double Metric(int port, const std::string& name) {
  httplib::Client c("127.0.0.1", port);
  auto r = c.Get("/metrics");
  if (!r) return -1;
  auto e = metrics::ParseExposition(r->body);
  if (!e.ok()) return -1;
  auto v = e->Value(name);
  return v.ok() ? *v : -1;
}

class Vda5050Mqtt : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = std::make_unique<testing::ScratchDir>("vda5050_mqtt"); }
  // A supervisor publishing VDA 5050 to 127.0.0.1:port, with `vda` JSON members added.
  std::unique_ptr<testing::SupervisorProcess> Supervisor(const std::string& name, int port,
                                                         const std::string& vda = "") {
    const std::filesystem::path dir = dir_->path() / name;
    std::filesystem::create_directories(dir);
    std::ofstream(dir / "sup.json")
        << R"({"supervisor_id": "sup-v", "vda5050": {"enabled": true, "host": "127.0.0.1", "port": )"
        << port
        << R"(, "manufacturer": "acme", "rate_hz": 5, "keepalive_s": 5, "reconnect_max_s": 1,
        "serial_numbers": {"agv-v1": "SN-001"})"
        << vda << R"(}, "metrics": {"port": 0, "port_file": ")" << (dir / "metrics_port").string()
        << "\"}}";
    return std::make_unique<testing::SupervisorProcess>(
        dir, kDomain, "vda5050-test-token-01",
        std::vector<std::string>{"--config", (dir / "sup.json").string()});
  }
  int MetricsPort(const std::string& name) {
    int port = 0;
    Eventually(
        [&] {
          std::ifstream in(dir_->path() / name / "metrics_port");
          return static_cast<bool>(in >> port);
        },
        10);
    return port;
  }
  std::unique_ptr<testing::ScratchDir> dir_;
};

TEST_F(Vda5050Mqtt, VisualizationAndConnectionReachTheBrokerAndSurviveItsRestart) {
  const int port = FreePort();
  Broker broker(dir_->path(), port);
  auto supervisor = Supervisor("sup", port);
  auto participant = transport::Participant::Create(kDomain);
  ASSERT_TRUE(participant.ok());
  testing::FakeVehicle vehicle(*participant, "agv-v1"), other(*participant, "agv-v2");
  std::atomic<bool> driving{true};
  std::thread drive([&] {
    for (double x = 0; driving; x += 0.01) {
      vehicle.Publish(x);
      other.Publish(-x);
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
  });
  // The retained connection state, then three visualization messages of the mapped vehicle and
  // one of the unmapped one (published under its vehicle id).
  std::vector<std::string> connection;
  EXPECT_TRUE(Eventually(
      [&] {
        connection = broker.Subscribe("uagv/v2/acme/sup-v/connection", 1, 2);
        return connection.size() == 1 &&
               Payload(connection[0]).value("connectionState", "") == "ONLINE";
      },
      15))
      << supervisor->log();
  if (!connection.empty()) {
    EXPECT_EQ(HeaderMisfit(Payload(connection[0]), "sup-v"), "");
    EXPECT_EQ(SchemaMisfit(dir_->path(), "connection.schema.json", Payload(connection[0])), "");
  }
  const std::vector<std::string> lines =
      broker.Subscribe("uagv/v2/acme/SN-001/visualization", 3, 10);
  ASSERT_EQ(lines.size(), 3u) << supervisor->log();
  long long last_id = -1;
  for (const std::string& line : lines) {
    const json m = Payload(line);
    EXPECT_EQ(VisualizationMisfit(m, "SN-001"), "") << line;
    EXPECT_EQ(SchemaMisfit(dir_->path(), "visualization.schema.json", m), "") << line;
    EXPECT_GT(m.value("headerId", -1LL), last_id) << "headerId must grow per topic";
    last_id = m.value("headerId", -1LL);
    EXPECT_EQ(m["agvPosition"].value("positionInitialized", false), true);
    EXPECT_NEAR(m["agvPosition"].value("y", 0.0), 0.25, 1e-9);
  }
  EXPECT_EQ(broker.Subscribe("uagv/v2/acme/agv-v2/visualization", 1, 5).size(), 1u);

  // The broker goes away: the supervisor counts the loss, names the issue and keeps serving.
  const int metrics_port = MetricsPort("sup");
  broker.Kill();
  EXPECT_TRUE(Eventually(
      [&] {
        return Metric(metrics_port, "fleetloc_supervisor_vda5050_connection_losses_total") >= 1;
      },
      15));
  EXPECT_TRUE(Eventually(
      [&] {
        return supervisor->log().find("vda5050_broker_unreachable") != std::string::npos ||
               supervisor->log().find("lost the connection") != std::string::npos;
      },
      5));
  EXPECT_EQ(Metric(metrics_port, "fleetloc_supervisor_vda5050_connected"), 0);
  EXPECT_TRUE(HealthNames(*participant, "vda5050_broker_unreachable"));
  httplib::Client api("127.0.0.1", supervisor->port());
  auto fleet = api.Get("/api/fleet");
  ASSERT_TRUE(fleet);
  EXPECT_EQ(fleet->status, 200);
  EXPECT_NE(fleet->body.find("agv-v1"), std::string::npos);
  // ... and comes back: reconnected, ONLINE again, messages flow.
  broker.Start();
  EXPECT_TRUE(Eventually(
      [&] { return Metric(metrics_port, "fleetloc_supervisor_vda5050_connects_total") >= 2; }, 20))
      << supervisor->log();
  EXPECT_EQ(broker.Subscribe("uagv/v2/acme/SN-001/visualization", 1, 5).size(), 1u);
  EXPECT_EQ(Metric(metrics_port, "fleetloc_supervisor_vda5050_connected"), 1);

  // The supervisor dies: the broker publishes its last will, retained.
  supervisor->Crash();
  std::vector<std::string> will;
  EXPECT_TRUE(Eventually(
      [&] {
        will = broker.Subscribe("uagv/v2/acme/sup-v/connection", 1, 2);
        return will.size() == 1 &&
               Payload(will[0]).value("connectionState", "") == "CONNECTIONBROKEN";
      },
      20))
      << (will.empty() ? "" : will[0]);
  if (!will.empty()) {
    EXPECT_EQ(SchemaMisfit(dir_->path(), "connection.schema.json", Payload(will[0])), "");
  }
  driving = false;
  drive.join();
}

// A broker that speaks only TLS: the supervisor verifies it against the site's CA and publishes;
// a reader with the CA gets valid messages, one without TLS gets nothing from that listener.
TEST_F(Vda5050Mqtt, PublishesOverTlsToABrokerVerifiedByTheSitesCa) {
  const std::filesystem::path d = dir_->path();
  ASSERT_TRUE(MakeTlsFiles(d));
  const int port = FreePort();
  Broker broker(d, port,
                "cafile " + (d / "ca.crt").string() + "\ncertfile " + (d / "server.crt").string() +
                    "\nkeyfile " + (d / "server.key").string() + "\n",
                {"--cafile", (d / "ca.crt").string()});
  auto supervisor =
      Supervisor("tls", port, R"(, "tls": true, "ca_file": ")" + (d / "ca.crt").string() + "\"");
  auto participant = transport::Participant::Create(kDomain);
  ASSERT_TRUE(participant.ok());
  testing::FakeVehicle vehicle(*participant, "agv-v1");
  std::atomic<bool> driving{true};
  std::thread drive([&] {
    for (double x = 0; driving; x += 0.01) {
      vehicle.Publish(x);
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
  });
  std::vector<std::string> lines;
  EXPECT_TRUE(Eventually(
      [&] {
        lines = broker.Subscribe("uagv/v2/acme/SN-001/visualization", 1, 2);
        return lines.size() == 1;
      },
      20))
      << supervisor->log();
  if (!lines.empty()) {
    EXPECT_EQ(SchemaMisfit(d, "visualization.schema.json", Payload(lines[0])), "") << lines[0];
  }
  // Without TLS the listener answers nothing: the messages above went over TLS.
  const std::string out = (d / "plain.out").string();
  auto plain = runtime::ChildProcess::Start(
      "/usr/bin/mosquitto_sub",
      {"-h", "127.0.0.1", "-p", std::to_string(port), "-t", "uagv/#", "-C", "1", "-W", "2"}, out);
  ASSERT_TRUE(plain.ok());
  plain->Wait(std::chrono::seconds(7));
  std::ifstream in(out);
  const std::string got((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(got.find("agvPosition"), std::string::npos) << got;
  driving = false;
  drive.join();
}

TEST_F(Vda5050Mqtt, WrongCredentialsAreRefusedCountedAndNamed) {
  const int port = FreePort();
  const std::filesystem::path passwords = dir_->path() / "passwords";
  ASSERT_EQ(
      std::system(("mosquitto_passwd -c -b " + passwords.string() + " fleet right-secret").c_str()),
      0);
  Broker broker(dir_->path(), port,
                "allow_anonymous false\npassword_file " + passwords.string() + "\n");
  auto supervisor =
      Supervisor("wrong", port, R"(, "username": "fleet", "password": "wrong-secret")");
  const int metrics_port = MetricsPort("wrong");
  EXPECT_TRUE(Eventually(
      [&] { return Metric(metrics_port, "fleetloc_supervisor_vda5050_refused_total") >= 1; }, 15))
      << supervisor->log();
  EXPECT_NE(supervisor->log().find("refused"), std::string::npos);
  EXPECT_EQ(Metric(metrics_port, "fleetloc_supervisor_vda5050_connected"), 0);
  httplib::Client api("127.0.0.1", supervisor->port());
  auto stats = api.Get("/api/stats");
  ASSERT_TRUE(stats);
  EXPECT_EQ(stats->status, 200);
  // The right password connects.
  auto right = Supervisor(
      "right", port,
      R"(, "username": "fleet", "password": "right-secret", "client_id": "fleetloc-right")");
  const int right_port = MetricsPort("right");
  EXPECT_TRUE(Eventually(
      [&] { return Metric(right_port, "fleetloc_supervisor_vda5050_connected") == 1; }, 15))
      << right->log();
}

}  // namespace
}  // namespace fleetloc
