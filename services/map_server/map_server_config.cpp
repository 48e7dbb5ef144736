// Map server configuration from JSON.
#include "map_server/map_server_config.h"

#include <functional>
#include <set>

#include "io/json_fields.h"
#include "map_server/admission_config.h"
#include "transport/wire_util.h"

namespace fleetloc::map_server {

Status Validate(const MapServerConfig& c) {
  auto bad = [](const std::string& field, const std::string& what) {
    return InvalidInput("map server config: field '" + field + "': " + what);
  };
  if (!transport::IsValidEntityId(c.server_id))
    return bad("server_id", "must be 1-11 of [A-Za-z0-9_-]");
  if (c.mosaic_path.empty()) return bad("mosaic", "is required");
  if (c.domain_id < 0 || c.domain_id > 232) return bad("domain", "must be in [0, 232]");
  if (c.owned_tiles && c.owned_tiles->empty()) return bad("owned_tiles", "is empty");
  if (c.max_tiles_per_request < 1 || c.max_tiles_per_request > 256) {
    return bad("max_tiles_per_request", "must be in [1, 256]");
  }
  if (c.max_patch_bytes < 1024) return bad("max_patch_bytes", "must be >= 1024");
  if (c.max_patch_side_px < 16) return bad("max_patch_side_px", "must be >= 16");
  if (c.max_vehicles < 1) return bad("max_vehicles", "must be >= 1");
  if (c.tile_cache_mb < 0 || c.tile_cache_mb > 65536)
    return bad("tile_cache_mb", "must be in [0, 65536]");
  if (c.self_similarity_grid < 0 || c.self_similarity_grid > 16) {
    return bad("self_similarity_grid", "must be in [0, 16]");
  }
  if (!(c.health_period_s >= 0.05 && c.health_period_s <= 60)) {
    return bad("health_period_s", "must be in [0.05, 60]");
  }
  if (const std::string problem = PolicyProblem(c.remap_policy); !problem.empty()) {
    return bad("patch_admission", problem);
  }
  if (const std::string problem = IntakeProblem(c.intake); !problem.empty())
    return bad("patch_intake", problem);
  if (const std::string problem = RetentionProblem(c.retention); !problem.empty())
    return bad("retention", problem);
  return metrics::Validate(c.metrics, "map server config");
}

namespace {

Status ReadOwnedTiles(const io::JsonFields& fields, MapServerConfig* c) {
  Result<io::JsonFields> owned = fields.Object("owned_tiles");
  if (!owned.ok()) return owned.status();
  mosaic::TileOwnership o;
  int* targets[] = {&o.col_begin, &o.col_end, &o.row_begin, &o.row_end};
  const char* names[] = {"col_begin", "col_end", "row_begin", "row_end"};
  for (int i = 0; i < 4; ++i) {
    double value = 0;
    FLEETLOC_RETURN_IF_ERROR(owned->NonNegativeNumber(names[i], &value));
    *targets[i] = static_cast<int>(value);
  }
  c->owned_tiles = o;
  return Status::Ok();
}

// Every option a map server file may name; anything else is an error (a typo must not be
// silently ignored).
const std::set<std::string>& KnownOptions() {
  static const std::set<std::string> known = {"server_id",
                                              "mosaic",
                                              "domain",
                                              "dds_config",
                                              "owned_tiles",
                                              "max_tiles_per_request",
                                              "max_patch_bytes",
                                              "max_patch_side_px",
                                              "max_vehicles",
                                              "tile_cache_mb",
                                              "health_period_s",
                                              "serve_place_index",
                                              "self_similarity_grid",
                                              "patch_admission",
                                              "patch_intake",
                                              "retention",
                                              "metrics"};
  return known;
}

// The integer options (their ranges are checked by Validate()).
Status ReadIntOptions(const io::JsonFields& fields, MapServerConfig* c) {
  struct IntField {
    const char* key;
    int* target;
  };
  for (const IntField& f :
       {IntField{"domain", &c->domain_id},
        IntField{"max_tiles_per_request", &c->max_tiles_per_request},
        IntField{"max_patch_bytes", &c->max_patch_bytes},
        IntField{"max_patch_side_px", &c->max_patch_side_px},
        IntField{"max_vehicles", &c->max_vehicles}, IntField{"tile_cache_mb", &c->tile_cache_mb},
        IntField{"self_similarity_grid", &c->self_similarity_grid}}) {
    if (!fields.Has(f.key)) continue;
    double value = 0;
    FLEETLOC_RETURN_IF_ERROR(fields.NonNegativeNumber(f.key, &value));
    if (value != static_cast<int>(value)) return fields.Error(f.key, "must be an integer");
    *f.target = static_cast<int>(value);
  }
  return Status::Ok();
}

// The nested objects: patch intake, retention and patch admission.
Status ReadSections(const io::JsonFields& fields, const nlohmann::json& json, MapServerConfig* c) {
  using SectionReader = std::function<Status(const io::JsonFields&, const nlohmann::json&)>;
  const std::pair<const char*, SectionReader> sections[] = {
      {"patch_intake",
       [&](const auto& f, const auto& j) { return ReadPatchIntake(f, j, &c->intake); }},
      {"retention",
       [&](const auto& f, const auto& j) { return ReadRetention(f, j, &c->retention); }},
      {"patch_admission",
       [&](const auto& f, const auto& j) { return ReadRemapPolicy(f, j, &c->remap_policy); }}};
  for (const auto& [key, read] : sections) {
    if (!fields.Has(key)) continue;
    Result<io::JsonFields> object = fields.Object(key);
    if (!object.ok()) return object.status();
    FLEETLOC_RETURN_IF_ERROR(read(*object, json[key]));
  }
  return Status::Ok();
}

}  // namespace

Result<MapServerConfig> LoadMapServerConfig(const std::string& path) {
  Result<nlohmann::json> json = io::ReadJsonObjectFile(path);
  if (!json.ok()) return json.status();
  const io::JsonFields fields(*json, path);
  for (const auto& [key, value] : json->items()) {
    if (!KnownOptions().contains(key)) return fields.Error(key, "unknown option");
  }
  MapServerConfig c;
  if (fields.Has("server_id")) {
    FLEETLOC_RETURN_IF_ERROR(fields.NonEmptyString("server_id", &c.server_id));
  }
  if (fields.Has("mosaic"))
    FLEETLOC_RETURN_IF_ERROR(fields.NonEmptyString("mosaic", &c.mosaic_path));
  if (fields.Has("dds_config")) {
    FLEETLOC_RETURN_IF_ERROR(fields.NonEmptyString("dds_config", &c.dds_config_path));
  }
  FLEETLOC_RETURN_IF_ERROR(ReadIntOptions(fields, &c));
  if (fields.Has("health_period_s")) {
    FLEETLOC_RETURN_IF_ERROR(fields.PositiveNumber("health_period_s", &c.health_period_s));
  }
  if (fields.Has("owned_tiles")) FLEETLOC_RETURN_IF_ERROR(ReadOwnedTiles(fields, &c));
  if (fields.Has("serve_place_index")) {
    FLEETLOC_RETURN_IF_ERROR(fields.Bool("serve_place_index", &c.serve_place_index));
  }
  FLEETLOC_RETURN_IF_ERROR(ReadSections(fields, *json, &c));
  if (fields.Has("metrics")) {
    FLEETLOC_RETURN_IF_ERROR(metrics::ReadMetricsOptions(fields, *json, &c.metrics));
  }
  if (Status valid = Validate(c); !valid.ok()) return InvalidInput(path + ": " + valid.message());
  return c;
}

}  // namespace fleetloc::map_server
