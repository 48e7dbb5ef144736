// Tracker agent configuration from JSON.
#include "tracker_agent/agent_config.h"

#include <set>

#include "io/json_fields.h"
#include "transport/wire_util.h"

namespace fleetloc::tracker_agent {

Status Validate(const AgentConfig& c) {
  auto bad = [](const std::string& field, const std::string& what) {
    return InvalidInput("tracker agent config: field '" + field + "': " + what);
  };
  if (!transport::IsValidEntityId(c.vehicle_id))
    return bad("vehicle_id", "must be 1-11 of [A-Za-z0-9_-]");
  if (c.domain_id < 0 || c.domain_id > 232) return bad("domain", "must be in [0, 232]");
  if (c.source != "replay" && c.source != "sim" && !IsLiveSource(c.source)) {
    return bad("source", "must be replay, sim, aravis or gstreamer");
  }
  if (c.source == "replay" && c.run_path.empty())
    return bad("run", "is required (the replay source)");
  if (c.source == "sim" && c.sim_floor.empty())
    return bad("sim_floor", "is required (the sim source)");
  if (!(c.sim_resolution_m > 0)) return bad("sim_resolution_m", "must be > 0");
  if (!(c.sim_speed_px_s > 0)) return bad("sim_speed_px_s", "must be > 0");
  if (!(c.sim_rate_hz > 0 && c.sim_rate_hz <= 100))
    return bad("sim_rate_hz", "must be in (0, 100]");
  if (!(c.sim_start_fraction >= 0 && c.sim_start_fraction < 1))
    return bad("sim_start_fraction", "must be in [0, 1)");
  if (c.tile_cache_mb < 1) return bad("tile_cache_mb", "must be >= 1");
  if (c.tile_timeout_ms < 10) return bad("tile_timeout_ms", "must be >= 10");
  if (c.prefetch_margin_px < 0) return bad("prefetch_margin_px", "must be >= 0");
  if (!(c.prefetch_ahead_s >= 0 && c.prefetch_ahead_s <= 10))
    return bad("prefetch_ahead_s", "must be in [0, 10]");
  if (!(c.health_period_s >= 0.05 && c.health_period_s <= 60))
    return bad("health_period_s", "must be in [0.05, 60]");
  if (!(c.map_server_timeout_s >= 0.1)) return bad("map_server_timeout_s", "must be >= 0.1");
  if (!(c.mosaic_wait_s > 0)) return bad("mosaic_wait_s", "must be > 0");
  if (!(c.patch_min_interval_s > 0)) return bad("patch_min_interval_s", "must be > 0");
  if (!(c.patch_min_changed > 0 && c.patch_min_changed <= 1))
    return bad("patch_min_changed", "must be in (0, 1]");
  if (!(c.patch_retry_s > 0)) return bad("patch_retry_s", "must be > 0");
  if (!(c.drain_s >= 0)) return bad("drain_s", "must be >= 0");
  if (c.outbox_max_patches < 1) return bad("outbox_max_patches", "must be >= 1");
  if (c.outbox_max_mb < 1) return bad("outbox_max_mb", "must be >= 1");
  if (c.start_pose != "given" && c.start_pose != "relocalize") {
    return bad("start_pose", "must be given or relocalize");
  }
  if (c.relocalize_after_coasting_frames < 1)
    return bad("relocalize_after_coasting_frames", "must be >= 1");
  if (c.relocalize_trajectory_frames < 1 || c.relocalize_trajectory_frames > 20)
    return bad("relocalize_trajectory_frames", "must be 1..20");
  if (c.relocalize_threads < 1 || c.relocalize_threads > 2)
    return bad("relocalize_threads", "must be 1 or 2");
  if (!(c.relocalize_interval_s >= 0 && c.relocalize_interval_s <= 60)) {
    return bad("relocalize_interval_s", "must be in [0, 60]");
  }
  if (!(c.position_update_period_s >= 0.1 && c.position_update_period_s <= 60)) {
    return bad("position_update_period_s", "must be in [0.1, 60]");
  }
  if (!(c.position_update_window_s >= 0.1 && c.position_update_window_s <= 60)) {
    return bad("position_update_window_s", "must be in [0.1, 60]");
  }
  if (!(c.position_update_half_life_s >= 0 && c.position_update_half_life_s <= 60)) {
    return bad("position_update_half_life_s", "must be in [0, 60]");
  }
  FLEETLOC_RETURN_IF_ERROR(ValidateLive(c.source, c.live, c.ros));
  return metrics::Validate(c.metrics, "tracker agent config");
}

bool IsLiveSource(const std::string& source) { return source == "aravis" || source == "gstreamer"; }

namespace {

// The configuration's strings and integers (in `fields`) into *c.
Status ReadTextAndIntegerFields(const io::JsonFields& fields, AgentConfig* c) {
  for (const auto& [key, target] : {std::pair{"vehicle_id", &c->vehicle_id},
                                    {"dds_config", &c->dds_config_path},
                                    {"run", &c->run_path},
                                    {"tracker", &c->tracker_options_path},
                                    {"outbox", &c->outbox_path},
                                    {"source", &c->source},
                                    {"sim_floor", &c->sim_floor},
                                    {"start_pose", &c->start_pose},
                                    {"landmarks", &c->landmarks_path}}) {
    if (fields.Has(key)) FLEETLOC_RETURN_IF_ERROR(fields.NonEmptyString(key, target));
  }
  for (const auto& [key, target] :
       {std::pair{"domain", &c->domain_id},
        {"tile_cache_mb", &c->tile_cache_mb},
        {"tile_timeout_ms", &c->tile_timeout_ms},
        {"prefetch_margin_px", &c->prefetch_margin_px},
        {"sim_seed", &c->sim_seed},
        {"outbox_max_patches", &c->outbox_max_patches},
        {"outbox_max_mb", &c->outbox_max_mb},
        {"relocalize_after_coasting_frames", &c->relocalize_after_coasting_frames},
        {"relocalize_trajectory_frames", &c->relocalize_trajectory_frames},
        {"relocalize_threads", &c->relocalize_threads}}) {
    if (!fields.Has(key)) continue;
    double value = 0;
    FLEETLOC_RETURN_IF_ERROR(fields.NonNegativeNumber(key, &value));
    if (value != static_cast<int>(value)) return fields.Error(key, "must be an integer");
    *target = static_cast<int>(value);
  }
  return Status::Ok();
}

// The configuration's real numbers and flags (in `fields`) into *c.
Status ReadRealAndFlagFields(const io::JsonFields& fields, AgentConfig* c) {
  for (const auto& [key, target] : {std::pair{"health_period_s", &c->health_period_s},
                                    {"map_server_timeout_s", &c->map_server_timeout_s},
                                    {"mosaic_wait_s", &c->mosaic_wait_s},
                                    {"patch_min_interval_s", &c->patch_min_interval_s},
                                    {"patch_min_changed", &c->patch_min_changed},
                                    {"patch_retry_s", &c->patch_retry_s},
                                    {"sim_resolution_m", &c->sim_resolution_m},
                                    {"sim_speed_px_s", &c->sim_speed_px_s},
                                    {"sim_rate_hz", &c->sim_rate_hz},
                                    {"position_update_period_s", &c->position_update_period_s},
                                    {"position_update_window_s", &c->position_update_window_s}}) {
    if (fields.Has(key)) FLEETLOC_RETURN_IF_ERROR(fields.PositiveNumber(key, target));
  }
  if (fields.Has("sim_start_fraction")) {
    FLEETLOC_RETURN_IF_ERROR(
        fields.NonNegativeNumber("sim_start_fraction", &c->sim_start_fraction));
  }
  for (const auto& [key, target] :
       {std::pair{"drain_s", &c->drain_s},
        {"prefetch_ahead_s", &c->prefetch_ahead_s},
        {"relocalize_interval_s", &c->relocalize_interval_s},
        {"position_update_half_life_s", &c->position_update_half_life_s}}) {
    if (fields.Has(key)) FLEETLOC_RETURN_IF_ERROR(fields.NonNegativeNumber(key, target));
  }
  if (fields.Has("relocalize_on_lost")) {
    FLEETLOC_RETURN_IF_ERROR(fields.Bool("relocalize_on_lost", &c->relocalize_on_lost));
  }
  if (fields.Has("paced")) FLEETLOC_RETURN_IF_ERROR(fields.Bool("paced", &c->paced));
  return Status::Ok();
}

}  // namespace

Result<AgentConfig> LoadAgentConfig(const std::string& path) {
  Result<nlohmann::json> json = io::ReadJsonObjectFile(path);
  if (!json.ok()) return json.status();
  const io::JsonFields fields(*json, path);
  static const std::set<std::string> known = {"vehicle_id",
                                              "domain",
                                              "dds_config",
                                              "run",
                                              "paced",
                                              "tracker",
                                              "tile_cache_mb",
                                              "tile_timeout_ms",
                                              "prefetch_margin_px",
                                              "prefetch_ahead_s",
                                              "health_period_s",
                                              "map_server_timeout_s",
                                              "mosaic_wait_s",
                                              "outbox",
                                              "outbox_max_patches",
                                              "outbox_max_mb",
                                              "patch_min_interval_s",
                                              "patch_min_changed",
                                              "patch_retry_s",
                                              "drain_s",
                                              "source",
                                              "sim_floor",
                                              "sim_resolution_m",
                                              "sim_speed_px_s",
                                              "sim_rate_hz",
                                              "sim_start_fraction",
                                              "sim_seed",
                                              "start_pose",
                                              "relocalize_on_lost",
                                              "relocalize_after_coasting_frames",
                                              "relocalize_interval_s",
                                              "relocalize_trajectory_frames",
                                              "relocalize_threads",
                                              "landmarks",
                                              "position_update_period_s",
                                              "position_update_window_s",
                                              "position_update_half_life_s",
                                              "metrics",
                                              "camera",
                                              "live",
                                              "aravis",
                                              "gstreamer",
                                              "ros"};
  for (const auto& [key, value] : json->items()) {
    if (!known.contains(key)) return fields.Error(key, "unknown option");
  }
  AgentConfig c;
  FLEETLOC_RETURN_IF_ERROR(ReadTextAndIntegerFields(fields, &c));
  FLEETLOC_RETURN_IF_ERROR(ReadRealAndFlagFields(fields, &c));
  if (fields.Has("metrics"))
    FLEETLOC_RETURN_IF_ERROR(metrics::ReadMetricsOptions(fields, *json, &c.metrics));
  c.ros.enabled = IsLiveSource(c.source);  // the default; "ros.enabled" overrides
  FLEETLOC_RETURN_IF_ERROR(ReadLiveOptions(fields, *json, &c.live, &c.ros));
  if (Status valid = Validate(c); !valid.ok()) return InvalidInput(path + ": " + valid.message());
  return c;
}

}  // namespace fleetloc::tracker_agent
