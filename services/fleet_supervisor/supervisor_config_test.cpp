// Supervisor configuration: defaults, the shipped sample, and bad fields named.
#include "fleet_supervisor/supervisor_config.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace fleetloc::fleet_supervisor {
namespace {

std::string Write(const std::string& name, const std::string& text) {
  const auto path = std::filesystem::temp_directory_path() / ("sup_config_" + name + ".json");
  std::ofstream(path) << text;
  return path.string();
}

TEST(SupervisorConfig, DefaultsBindLoopbackAndAreValid) {
  const SupervisorConfig c;
  EXPECT_EQ(c.http_bind, "127.0.0.1");
  EXPECT_TRUE(Validate(c).ok());
  EXPECT_EQ(*ResolveMaintainerToken(c), "");
}

TEST(SupervisorConfig, ShippedSampleLoads) {
  auto config = LoadSupervisorConfig(std::string(FLEETLOC_SOURCE_DIR) +
                                     "/deploy/config/fleet_supervisor.json");
  ASSERT_TRUE(config.ok()) << config.status().message();
  // Its "http" block lists the defaults.
  const HttpLimits defaults;
  EXPECT_EQ(config->http.max_connections, defaults.max_connections);
  EXPECT_EQ(config->http.max_header_bytes, defaults.max_header_bytes);
  EXPECT_EQ(config->http.header_timeout_s, defaults.header_timeout_s);
  EXPECT_TRUE(config->http.allowed_hosts.empty());
  EXPECT_EQ(config->mosaic_name, "floor");
  EXPECT_EQ(config->js_dir, "/usr/share/javascript");  // Debian's libjs-leaflet and libjs-chart.js
}

TEST(SupervisorConfig, FieldsAndAlertRulesAreRead) {
  auto c = LoadSupervisorConfig(
      Write("ok", R"({"http_port": 9000, "maintainer_token": "s3cret-s3cret-s3cret",
      "retention_s": 3600, "alerts": {"cycle_p95_ms": {"raise_above": 40, "clear_below": 20}},
      "trail": {"length_s": 30}})"));
  ASSERT_TRUE(c.ok()) << c.status().message();
  EXPECT_EQ(c->http_port, 9000);
  EXPECT_EQ(c->retention_s, 3600);
  EXPECT_EQ(c->alerts.cycle_p95_ms.raise_above, 40);
  EXPECT_EQ(c->alerts.cycle_p95_ms.clear_below, 20);
  EXPECT_EQ(c->alerts.cycle_p95_ms.raise_after_s, 3.0);  // default kept
  EXPECT_EQ(c->trail.length_s, 30);
  EXPECT_EQ(*ResolveMaintainerToken(*c), "s3cret-s3cret-s3cret");
}

// Writes a token file with `mode`.
std::string WriteToken(const std::string& name, const std::string& text,
                       std::filesystem::perms mode) {
  // A read-only file of an earlier run could not be written over: start afresh.
  std::filesystem::remove(std::filesystem::temp_directory_path() /
                          ("sup_config_" + name + ".json"));
  const std::string path = Write(name, text);
  std::filesystem::permissions(path, mode);
  return path;
}

TEST(SupervisorConfig, TokenFileFirstLineIsTheToken) {
  using std::filesystem::perms;
  SupervisorConfig c;
  c.maintainer_token_file = WriteToken("token", "abc123-abc123-abc123\nignored\n",
                                       perms::owner_read | perms::owner_write);
  EXPECT_EQ(*ResolveMaintainerToken(c), "abc123-abc123-abc123");
  c.maintainer_token_file = "/nonexistent/token";
  EXPECT_FALSE(ResolveMaintainerToken(c).ok());
}

TEST(SupervisorConfig, ATokenFileOthersCanReadOrAShortTokenIsRefused) {
  using std::filesystem::perms;
  SupervisorConfig c;
  c.maintainer_token_file = WriteToken("token_world", "abc123-abc123-abc123\n",
                                       perms::owner_read | perms::owner_write | perms::others_read);
  auto resolved = ResolveMaintainerToken(c);
  ASSERT_FALSE(resolved.ok());
  EXPECT_NE(resolved.status().message().find("mode 604"), std::string::npos)
      << resolved.status().message();
  c.maintainer_token_file =
      WriteToken("token_group", "abc123-abc123-abc123\n", perms::owner_read | perms::group_read);
  EXPECT_NE(ResolveMaintainerToken(c).status().message().find("mode 440"), std::string::npos);
  c.maintainer_token_file = WriteToken("token_short", "abc123\n", perms::owner_read);
  EXPECT_NE(ResolveMaintainerToken(c).status().message().find("shorter than 16"),
            std::string::npos);
  c.maintainer_token_file = WriteToken("token_space", "abc123 abc123 abc123\n", perms::owner_read);
  EXPECT_NE(ResolveMaintainerToken(c).status().message().find("printable"), std::string::npos);
  c.maintainer_token_file.clear();
  c.maintainer_token = "short";
  EXPECT_NE(ResolveMaintainerToken(c).status().message().find("maintainer_token"),
            std::string::npos);
}

TEST(SupervisorConfig, HttpLimitsAreReadAndChecked) {
  auto c = LoadSupervisorConfig(Write("http", R"({"http": {"max_connections": 100, "workers": 4,
      "header_timeout_s": 2.5, "allowed_hosts": ["fleet.example.org", "10.0.0.5"]}})"));
  ASSERT_TRUE(c.ok()) << c.status().message();
  EXPECT_EQ(c->http.max_connections, 100);
  EXPECT_EQ(c->http.workers, 4);
  EXPECT_EQ(c->http.header_timeout_s, 2.5);
  EXPECT_EQ(c->http.allowed_hosts, (std::vector<std::string>{"fleet.example.org", "10.0.0.5"}));
  EXPECT_EQ(c->http.max_streams, HttpLimits{}.max_streams);  // default kept
}

TEST(SupervisorConfig, MetricsAreOnByDefaultAndConfigurable) {
  EXPECT_TRUE(SupervisorConfig{}.metrics.enabled);
  EXPECT_EQ(SupervisorConfig{}.metrics.port, 9472);
  auto c = LoadSupervisorConfig(
      Write("metrics", R"({"metrics": {"enabled": false, "port": 9500, "threads": 2}})"));
  ASSERT_TRUE(c.ok()) << c.status().message();
  EXPECT_FALSE(c->metrics.enabled);
  EXPECT_EQ(c->metrics.port, 9500);
  EXPECT_EQ(c->metrics.threads, 2);
  EXPECT_EQ(c->metrics.bind, "127.0.0.1");  // default kept
}

TEST(SupervisorConfig, Vda5050IsOffByDefaultAndReadWithItsSerialNumbers) {
  EXPECT_FALSE(SupervisorConfig{}.vda5050.enabled);
  auto c = LoadSupervisorConfig(
      Write("vda", R"({"vda5050": {"enabled": true, "host": "broker.site", "port": 8883,
      "username": "fleet", "password_file": "/etc/fleetloc/mqtt_password", "tls": true, "ca_file": "/etc/ca.pem",
      "interface_name": "site-a", "manufacturer": "acme", "rate_hz": 2, "max_pose_age_s": 5,
      "serial_numbers": {"agv-1": "SN-001"}, "connection_serial": "fleetloc-sup"}})"));
  ASSERT_TRUE(c.ok()) << c.status().message();
  const Vda5050Options& v = c->vda5050;
  EXPECT_TRUE(v.enabled);
  EXPECT_EQ(v.host, "broker.site");
  EXPECT_EQ(v.port, 8883);
  EXPECT_TRUE(v.tls);
  EXPECT_EQ(v.header.interface_name, "site-a");
  EXPECT_EQ(v.header.manufacturer, "acme");
  EXPECT_EQ(v.rate_hz, 2);
  EXPECT_EQ(v.serial_numbers.at("agv-1"), "SN-001");
  EXPECT_EQ(v.connection_serial, "fleetloc-sup");
  EXPECT_EQ(v.keepalive_s, 10);  // default kept
}

TEST(SupervisorConfig, BadFieldsAreNamed) {
  const std::pair<const char*, const char*> cases[] = {
      {R"({"colour": 1})", "colour"},
      {R"({"supervisor_id": "a*b"})", "supervisor_id"},
      {R"({"http_port": 70000})", "http_port"},
      {R"({"http_port": 80.5})", "http_port"},
      {R"({"retention_s": 5})", "retention_s"},
      {R"({"alerts": {"boredom": {}}})", "boredom"},
      {R"({"alerts": {"silent_s": {"raise_above": 1, "clear_below": 2}}})", "alerts"},
      {R"({"alerts": {"silent_s": {"raise_abov": 1}}})", "raise_abov"},
      {R"({"trail": {"period_s": -1}})", "period_s"},
      {R"({"http_bind": ""})", "http_bind"},
      {R"({"http": {"workers": 0}})", "workers"},
      {R"({"http": {"max_conections": 5}})", "max_conections"},
      {R"({"http": {"allowed_hosts": "x"}})", "allowed_hosts"},
      {R"({"http": {"allowed_hosts": ["a b"]}})", "allowed_hosts"},
      {R"({"metrics": {"prot": 1}})", "metrics.prot"},
      {R"({"metrics": {"port": -1}})", "metrics.port"},
      {R"({"vda5050": {"brokr": "x"}})", "vda5050.brokr"},
      {R"({"vda5050": {"enabled": true, "port": 0}})", "vda5050.port"},
      {R"({"vda5050": {"enabled": true, "rate_hz": 100}})", "vda5050.rate_hz"},
      {R"({"vda5050": {"enabled": true, "manufacturer": "a/b"}})", "vda5050.manufacturer"},
      {R"({"vda5050": {"enabled": true, "password": "p"}})", "vda5050.username"},
      {R"({"vda5050": {"enabled": true, "tls": true}})", "vda5050.ca_file"},
      {R"({"vda5050": {"enabled": true, "serial_numbers": {"agv-1": "a#b"}}})",
       "serial_numbers.agv-1"},
      {R"({"vda5050": {"serial_numbers": ["x"]}})", "serial_numbers"},
  };
  for (const auto& [json, field] : cases) {
    auto c = LoadSupervisorConfig(Write("bad", json));
    ASSERT_FALSE(c.ok()) << json;
    EXPECT_NE(c.status().message().find(field), std::string::npos) << c.status().message();
  }
}

}  // namespace
}  // namespace fleetloc::fleet_supervisor
