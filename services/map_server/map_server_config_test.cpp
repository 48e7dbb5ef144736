// Map server configuration: defaults, overrides, and a one-line error naming each bad field.
#include "map_server/map_server_config.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace fleetloc::map_server {
namespace {

std::string WriteConfig(const std::string& name, const std::string& text) {
  const auto path = std::filesystem::temp_directory_path() / ("map_server_config_" + name + ".json");
  std::ofstream(path) << text;
  return path.string();
}

TEST(MapServerConfig, ReadsFieldsOverDefaults) {
  auto config = LoadMapServerConfig(WriteConfig(
      "ok", R"({"server_id": "map-2", "mosaic": "/data/m.db", "domain": 7,
                "owned_tiles": {"col_begin": 0, "col_end": 4, "row_begin": 2, "row_end": 9}})"));
  ASSERT_TRUE(config.ok()) << config.status().message();
  EXPECT_EQ(config->server_id, "map-2");
  EXPECT_EQ(config->mosaic_path, "/data/m.db");
  EXPECT_EQ(config->domain_id, 7);
  ASSERT_TRUE(config->owned_tiles.has_value());
  EXPECT_EQ(config->owned_tiles->col_end, 4);
  EXPECT_EQ(config->owned_tiles->row_begin, 2);
  EXPECT_EQ(config->max_tiles_per_request, 256);  // default kept
}

TEST(MapServerConfig, ShippedSampleConfigLoads) {
  auto config = LoadMapServerConfig(std::string(FLEETLOC_SOURCE_DIR) +
                                    "/deploy/config/map_server.json");
  ASSERT_TRUE(config.ok()) << config.status().message();
}

struct BadCase {
  const char* json;
  const char* field;
};

TEST(MapServerConfig, BadFieldsAreNamed) {
  const BadCase cases[] = {
      {R"({"mosaic": "m.db", "colour": 1})", "colour"},
      {R"({"mosaic": "m.db", "server_id": "a*b"})", "server_id"},
      {R"({"mosaic": "m.db", "server_id": "much-too-long-id"})", "server_id"},
      {R"({"server_id": "m"})", "mosaic"},
      {R"({"mosaic": "m.db", "domain": 999})", "domain"},
      {R"({"mosaic": "m.db", "domain": 1.5})", "domain"},
      {R"({"mosaic": "m.db", "max_tiles_per_request": 0})", "max_tiles_per_request"},
      {R"({"mosaic": "m.db", "health_period_s": -1})", "health_period_s"},
      {R"({"mosaic": "m.db", "owned_tiles": {"col_begin": 3, "col_end": 3, "row_begin": 0, "row_end": 1}})",
       "owned_tiles"},
  };
  int i = 0;
  for (const BadCase& c : cases) {
    auto config = LoadMapServerConfig(WriteConfig("bad" + std::to_string(i++), c.json));
    ASSERT_FALSE(config.ok()) << c.json;
    EXPECT_EQ(config.status().code(), StatusCode::kInvalidInput);
    EXPECT_NE(config.status().message().find(c.field), std::string::npos)
        << config.status().message();
  }
}

TEST(MapServerConfig, MissingFileIsNotFound) {
  auto config = LoadMapServerConfig("/nonexistent/map_server.json");
  ASSERT_FALSE(config.ok());
  EXPECT_EQ(config.status().code(), StatusCode::kNotFound);
}

}  // namespace
}  // namespace fleetloc::map_server
