// Map server configuration: defaults, overrides, and a one-line error naming each bad field.
#include "map_server/map_server_config.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace fleetloc::map_server {
namespace {

std::string WriteConfig(const std::string& name, const std::string& text) {
  const auto path =
      std::filesystem::temp_directory_path() / ("map_server_config_" + name + ".json");
  std::ofstream(path) << text;
  return path.string();
}

TEST(MapServerConfig, ReadsFieldsOverDefaults) {
  auto config = LoadMapServerConfig(
      WriteConfig("ok", R"({"server_id": "map-2", "mosaic": "/data/m.db", "domain": 7,
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
  auto config =
      LoadMapServerConfig(std::string(FLEETLOC_SOURCE_DIR) + "/deploy/config/map_server.json");
  ASSERT_TRUE(config.ok()) << config.status().message();
  // Its patch_admission block lists the defaults.
  const mosaic_upkeep::RemapPolicy defaults;
  const mosaic_upkeep::RemapPolicy& p = config->remap_policy;
  EXPECT_NEAR(p.admission.max_search_sigma_rad, defaults.admission.max_search_sigma_rad, 1e-9);
  EXPECT_NEAR(p.admission.min_disagreement_rad, defaults.admission.min_disagreement_rad, 1e-9);
  EXPECT_EQ(p.admission.min_inliers, defaults.admission.min_inliers);
  EXPECT_EQ(p.admission.blocks.block_px, defaults.admission.blocks.block_px);
  EXPECT_EQ(p.admission.max_changed_fraction, defaults.admission.max_changed_fraction);
  EXPECT_EQ(p.admission.max_flattened_fraction, defaults.admission.max_flattened_fraction);
  EXPECT_EQ(p.corroboration.min_vehicles, defaults.corroboration.min_vehicles);
  EXPECT_EQ(p.reputation.window, defaults.reputation.window);
  EXPECT_EQ(p.reputation.max_refused_fraction, defaults.reputation.max_refused_fraction);
  // So do its patch_intake and retention blocks.
  EXPECT_EQ(config->intake.budget.max_bytes_total, PatchBudgetOptions{}.max_bytes_total);
  EXPECT_EQ(config->intake.queue, PatchIntake{}.queue);
  EXPECT_EQ(config->retention.policy.unfolded_patch_retention_s,
            mosaic::RetentionPolicy{}.unfolded_patch_retention_s);
  EXPECT_EQ(config->retention.prune_period_s, Retention{}.prune_period_s);
  EXPECT_EQ(config->self_similarity_grid, MapServerConfig{}.self_similarity_grid);
}

struct BadCase {
  const char* json;
  const char* field;
};

TEST(MapServerConfig, MetricsAreOnByDefaultAndConfigurable) {
  EXPECT_TRUE(MapServerConfig{}.metrics.enabled);
  EXPECT_EQ(MapServerConfig{}.metrics.port, 9471);
  auto config = LoadMapServerConfig(
      WriteConfig("metrics", R"({"mosaic": "m.db", "metrics": {"port": 0, "bind": "::1"}})"));
  ASSERT_TRUE(config.ok()) << config.status().message();
  EXPECT_EQ(config->metrics.port, 0);
  EXPECT_EQ(config->metrics.bind, "::1");
  EXPECT_TRUE(config->metrics.enabled);
}

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
      {R"({"mosaic": "m.db", "patch_admission": {"trust_the_vehicle": true}})",
       "trust_the_vehicle"},
      {R"({"mosaic": "m.db", "patch_admission": {"max_changed_fraction": 1.5}})",
       "max_changed_fraction"},
      {R"({"mosaic": "m.db", "patch_admission": {"min_vehicles_per_change": 0}})",
       "min_vehicles_per_change"},
      {R"({"mosaic": "m.db", "patch_admission": {"quarantine_window": 2}})",
       "quarantine_min_judged"},
      {R"({"mosaic": "m.db", "patch_admission": 3})", "patch_admission"},
      {R"({"mosaic": "m.db", "patch_intake": {"patches_per_s": 0}})", "patches_per_s"},
      {R"({"mosaic": "m.db", "patch_intake": {"burst": 2.5}})", "burst"},
      {R"({"mosaic": "m.db", "patch_intake": {"max_store_mb": 10, "max_mb_per_vehicle": 20}})",
       "max_store_mb"},
      {R"({"mosaic": "m.db", "patch_intake": {"flood": 1}})", "flood"},
      {R"({"mosaic": "m.db", "retention": {"tile_versions_kept": 0}})", "tile_versions_kept"},
      {R"({"mosaic": "m.db", "retention": {"prune_period_s": 1}})", "prune_period_s"},
      {R"({"mosaic": "m.db", "self_similarity_grid": 17})", "self_similarity_grid"},
      {R"({"mosaic": "m.db", "self_similarity_grid": 2.5})", "self_similarity_grid"},
      {R"({"mosaic": "m.db", "metrics": {"ports": 1}})", "metrics.ports"},
      {R"({"mosaic": "m.db", "metrics": {"threads": 0}})", "metrics.threads"},
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

TEST(MapServerConfig, PatchAdmissionIsReadInTheFilesUnits) {
  auto config = LoadMapServerConfig(WriteConfig(
      "admission", R"({"mosaic": "m.db", "patch_admission": {"min_vehicles_per_change": 2,
                       "max_search_sigma_deg": 2.0, "max_changed_fraction": 0.4,
                       "quarantine_window": 8, "quarantine_min_judged": 4}})"));
  ASSERT_TRUE(config.ok()) << config.status().message();
  const mosaic_upkeep::RemapPolicy& p = config->remap_policy;
  EXPECT_EQ(p.corroboration.min_vehicles, 2);
  EXPECT_NEAR(p.admission.max_search_sigma_rad, 2.0 * M_PI / 180, 1e-12);
  EXPECT_EQ(p.admission.max_changed_fraction, 0.4);
  EXPECT_EQ(p.reputation.window, 8);
  EXPECT_EQ(p.admission.min_inliers, mapping::AdmissionOptions{}.min_inliers);  // default kept
}

TEST(MapServerConfig, PatchIntakeAndRetentionAreReadInTheFilesUnits) {
  auto config = LoadMapServerConfig(WriteConfig(
      "intake",
      R"({"mosaic": "m.db", "patch_intake": {"patches_per_s": 0.5, "max_mb_per_vehicle": 64,
                    "max_store_mb": 1024}, "retention": {"tile_versions_kept": 3, "patch_retention_days": 2}})"));
  ASSERT_TRUE(config.ok()) << config.status().message();
  EXPECT_EQ(config->intake.budget.patches_per_s, 0.5);
  EXPECT_EQ(config->intake.budget.max_bytes_per_vehicle, 64LL << 20);
  EXPECT_EQ(config->intake.budget.max_bytes_total, 1024LL << 20);
  EXPECT_EQ(config->intake.budget.burst, PatchBudgetOptions{}.burst);  // default kept
  EXPECT_EQ(config->retention.policy.tile_versions_kept, 3);
  EXPECT_EQ(config->retention.policy.patch_retention_s, 2 * 86400.0);
  EXPECT_EQ(config->retention.prune_period_s, 3600);
}

TEST(MapServerConfig, MissingFileIsNotFound) {
  auto config = LoadMapServerConfig("/nonexistent/map_server.json");
  ASSERT_FALSE(config.ok());
  EXPECT_EQ(config.status().code(), StatusCode::kNotFound);
}

}  // namespace
}  // namespace fleetloc::map_server
