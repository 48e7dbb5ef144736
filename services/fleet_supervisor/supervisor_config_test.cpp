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
  auto config = LoadSupervisorConfig(std::string(FLEETLOC_SOURCE_DIR) + "/deploy/config/fleet_supervisor.json");
  ASSERT_TRUE(config.ok()) << config.status().message();
}

TEST(SupervisorConfig, FieldsAndAlertRulesAreRead) {
  auto c = LoadSupervisorConfig(Write("ok", R"({"http_port": 9000, "maintainer_token": "s3cret",
      "retention_s": 3600, "alerts": {"cycle_p95_ms": {"raise_above": 40, "clear_below": 20}},
      "trail": {"length_s": 30}})"));
  ASSERT_TRUE(c.ok()) << c.status().message();
  EXPECT_EQ(c->http_port, 9000);
  EXPECT_EQ(c->retention_s, 3600);
  EXPECT_EQ(c->alerts.cycle_p95_ms.raise_above, 40);
  EXPECT_EQ(c->alerts.cycle_p95_ms.clear_below, 20);
  EXPECT_EQ(c->alerts.cycle_p95_ms.raise_after_s, 3.0);  // default kept
  EXPECT_EQ(c->trail.length_s, 30);
  EXPECT_EQ(*ResolveMaintainerToken(*c), "s3cret");
}

TEST(SupervisorConfig, TokenFileFirstLineIsTheToken) {
  SupervisorConfig c;
  c.maintainer_token_file = Write("token", "abc123\nignored\n");
  EXPECT_EQ(*ResolveMaintainerToken(c), "abc123");
  c.maintainer_token_file = "/nonexistent/token";
  EXPECT_FALSE(ResolveMaintainerToken(c).ok());
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
  };
  for (const auto& [json, field] : cases) {
    auto c = LoadSupervisorConfig(Write("bad", json));
    ASSERT_FALSE(c.ok()) << json;
    EXPECT_NE(c.status().message().find(field), std::string::npos) << c.status().message();
  }
}

}  // namespace
}  // namespace fleetloc::fleet_supervisor
