// Tracker agent configuration: fields over defaults, the shipped sample loads, bad fields named.
#include "tracker_agent/agent_config.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace fleetloc::tracker_agent {
namespace {

std::string Write(const std::string& name, const std::string& text) {
  const auto path = std::filesystem::temp_directory_path() / ("agent_config_" + name + ".json");
  std::ofstream(path) << text;
  return path.string();
}

TEST(AgentConfig, ReadsFieldsOverDefaults) {
  auto c = LoadAgentConfig(Write("ok", R"({"vehicle_id": "agv-3", "run": "/runs/a", "paced": false,
                                           "domain": 4, "tile_cache_mb": 32,
                                           "map_server_timeout_s": 5})"));
  ASSERT_TRUE(c.ok()) << c.status().message();
  EXPECT_EQ(c->vehicle_id, "agv-3");
  EXPECT_EQ(c->run_path, "/runs/a");
  EXPECT_FALSE(c->paced);
  EXPECT_EQ(c->domain_id, 4);
  EXPECT_EQ(c->tile_cache_mb, 32);
  EXPECT_EQ(c->tile_timeout_ms, 2000);
  EXPECT_EQ(c->map_server_timeout_s, 5.0);
  EXPECT_EQ(c->start_pose, "given");
  EXPECT_TRUE(c->relocalize_on_lost);
}

TEST(AgentConfig, ReadsRelocalizationFields) {
  auto c = LoadAgentConfig(Write("reloc", R"({"run": "/runs/a", "start_pose": "relocalize",
                                              "relocalize_on_lost": false,
                                              "relocalize_after_coasting_frames": 3,
                                              "relocalize_interval_s": 0.25,
                                              "relocalize_trajectory_frames": 4,
                                              "relocalize_threads": 1})"));
  ASSERT_TRUE(c.ok()) << c.status().message();
  EXPECT_EQ(c->start_pose, "relocalize");
  EXPECT_FALSE(c->relocalize_on_lost);
  EXPECT_EQ(c->relocalize_after_coasting_frames, 3);
  EXPECT_EQ(c->relocalize_interval_s, 0.25);
  EXPECT_EQ(c->relocalize_trajectory_frames, 4);
  EXPECT_EQ(c->relocalize_threads, 1);
  for (const char* threads : {"0", "3", "1.5"}) {
    EXPECT_FALSE(LoadAgentConfig(Write("reloc_threads", std::string(R"({"run": "/runs/a",
                                                          "relocalize_threads": )") +
                                                            threads + "}"))
                     .ok())
        << threads;
  }
  EXPECT_FALSE(LoadAgentConfig(Write("reloc_frames", R"({"run": "/runs/a",
                                                         "relocalize_trajectory_frames": 0})"))
                   .ok());
}

TEST(AgentConfig, ReadsPositionUpdateFields) {
  auto defaults = LoadAgentConfig(Write("gpu_defaults", R"({"run": "/runs/a"})"));
  ASSERT_TRUE(defaults.ok()) << defaults.status().message();
  EXPECT_EQ(defaults->landmarks_path, "");
  EXPECT_EQ(defaults->position_update_period_s, 1.0);
  auto c = LoadAgentConfig(Write("gpu", R"({"run": "/runs/a", "landmarks": "/maps/l.csv",
                                            "position_update_period_s": 0.5,
                                            "position_update_window_s": 3,
                                            "position_update_half_life_s": 0})"));
  ASSERT_TRUE(c.ok()) << c.status().message();
  EXPECT_EQ(c->landmarks_path, "/maps/l.csv");
  EXPECT_EQ(c->position_update_period_s, 0.5);
  EXPECT_EQ(c->position_update_window_s, 3.0);
  EXPECT_EQ(c->position_update_half_life_s, 0.0);
}

TEST(AgentConfig, ShippedSampleLoads) {
  auto c = LoadAgentConfig(FLEETLOC_SOURCE_DIR "/deploy/config/tracker_agent.json");
  ASSERT_TRUE(c.ok()) << c.status().message();
}

TEST(AgentConfig, MetricsAreOffByDefaultAndConfigurable) {
  EXPECT_FALSE(AgentConfig{}.metrics.enabled);
  auto c = LoadAgentConfig(
      Write("metrics", R"({"run": "r", "metrics": {"enabled": true, "port": 9600}})"));
  ASSERT_TRUE(c.ok()) << c.status().message();
  EXPECT_TRUE(c->metrics.enabled);
  EXPECT_EQ(c->metrics.port, 9600);
}

TEST(AgentConfig, BadFieldsAreNamed) {
  const std::pair<const char*, const char*> cases[] = {
      {R"({"run": "r", "wheels": 4})", "wheels"},
      {R"({"run": "r", "outbox_max_patches": 0})", "outbox_max_patches"},
      {R"({"run": "r", "outbox_max_mb": 1.5})", "outbox_max_mb"},
      {R"({"run": "r", "vehicle_id": "agv 7"})", "vehicle_id"},
      {R"({"vehicle_id": "a"})", "run"},
      {R"({"run": "r", "paced": "yes"})", "paced"},
      {R"({"run": "r", "tile_timeout_ms": 1})", "tile_timeout_ms"},
      {R"({"run": "r", "domain": 300})", "domain"},
      {R"({"run": "r", "map_server_timeout_s": 0.01})", "map_server_timeout_s"},
      {R"({"run": "r", "start_pose": "guess"})", "start_pose"},
      {R"({"run": "r", "relocalize_on_lost": 1})", "relocalize_on_lost"},
      {R"({"run": "r", "relocalize_after_coasting_frames": 0})",
       "relocalize_after_coasting_frames"},
      {R"({"run": "r", "relocalize_interval_s": 100})", "relocalize_interval_s"},
      {R"({"run": "r", "landmarks": ""})", "landmarks"},
      {R"({"run": "r", "position_update_period_s": 0.01})", "position_update_period_s"},
      {R"({"run": "r", "position_update_period_s": 0})", "position_update_period_s"},
      {R"({"run": "r", "position_update_window_s": 100})", "position_update_window_s"},
      {R"({"run": "r", "position_update_half_life_s": -1})", "position_update_half_life_s"},
      {R"({"run": "r", "metrics": {"enabled": true, "colour": 1}})", "metrics.colour"},
      {R"({"run": "r", "metrics": {"request_timeout_s": 100}})", "metrics.request_timeout_s"},
  };
  int i = 0;
  for (const auto& [json, field] : cases) {
    auto c = LoadAgentConfig(Write("bad" + std::to_string(i++), json));
    ASSERT_FALSE(c.ok()) << json;
    EXPECT_NE(c.status().message().find(field), std::string::npos) << c.status().message();
  }
}

}  // namespace
}  // namespace fleetloc::tracker_agent
