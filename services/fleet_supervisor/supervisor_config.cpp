// Fleet supervisor configuration from JSON.
#include "fleet_supervisor/supervisor_config.h"

#include <sys/stat.h>

#include <cstdio>
#include <set>

#include "io/file_util.h"
#include "io/json_fields.h"
#include "transport/wire_util.h"

namespace fleetloc::fleet_supervisor {

Status Validate(const SupervisorConfig& c) {
  auto bad = [](const std::string& field, const std::string& what) {
    return InvalidInput("fleet supervisor config: field '" + field + "': " + what);
  };
  if (!transport::IsValidEntityId(c.supervisor_id))
    return bad("supervisor_id", "must be 1-11 of [A-Za-z0-9_-]");
  if (c.domain_id < 0 || c.domain_id > 232) return bad("domain", "must be in [0, 232]");
  if (c.http_bind.empty()) return bad("http_bind", "is empty");
  if (c.http_port < 0 || c.http_port > 65535) return bad("http_port", "must be in [0, 65535]");
  if (c.history_db.empty()) return bad("history_db", "is empty");
  if (!(c.retention_s >= 60)) return bad("retention_s", "must be >= 60");
  if (!(c.history_period_s > 0 && c.history_period_s <= 3600))
    return bad("history_period_s", "must be in (0, 3600]");
  if (!(c.max_query_range_s > 0)) return bad("max_query_range_s", "must be > 0");
  if (c.max_history_points < 2 || c.max_history_points > 100000) {
    return bad("max_history_points", "must be in [2, 100000]");
  }
  if (!(c.stream_period_s >= 0.01 && c.stream_period_s <= 10))
    return bad("stream_period_s", "must be in [0.01, 10]");
  if (c.tile_cache_mb < 1 || c.tile_cache_mb > 4096)
    return bad("tile_cache_mb", "must be in [1, 4096]");
  if (c.min_tile_level < 0 || c.min_tile_level > 30)
    return bad("min_tile_level", "must be in [0, 30]");
  if (!(c.tile_timeout_s > 0 && c.tile_timeout_s <= 60))
    return bad("tile_timeout_s", "must be in (0, 60]");
  if (!(c.health_period_s >= 0.05 && c.health_period_s <= 60))
    return bad("health_period_s", "must be in [0.05, 60]");
  if (!(c.trail.period_s > 0 && c.trail.length_s >= c.trail.period_s)) {
    return bad("trail", "need period_s > 0 and length_s >= period_s");
  }
  if (Status alerts = fleet::Validate(c.alerts); !alerts.ok())
    return bad("alerts", alerts.message());
  if (const std::string problem = LimitsProblem(c.http); !problem.empty())
    return bad("http", problem);
  if (c.vda5050.enabled) FLEETLOC_RETURN_IF_ERROR(Validate(c.vda5050));
  return metrics::Validate(c.metrics, "fleet supervisor config");
}

namespace {

// "alerts": {"<rule>": {"raise_above", "clear_below", "raise_after_s", "clear_after_s"}}; every
// member optional.
Status ReadAlerts(const io::JsonFields& fields, const nlohmann::json& json,
                  fleet::AlertOptions* a) {
  const std::pair<const char*, fleet::HysteresisOptions*> rules[] = {
      {"silent_s", &a->silent_s},
      {"lock_lost", &a->lock_lost},
      {"uncertainty_m", &a->uncertainty_m},
      {"cycle_p95_ms", &a->cycle_p95_ms},
      {"camera_drops_per_s", &a->camera_drops_per_s},
      {"map_server_unreachable", &a->map_server_unreachable}};
  Result<io::JsonFields> alerts = fields.Object("alerts");
  if (!alerts.ok()) return alerts.status();
  for (const auto& [key, value] : json.items()) {
    fleet::HysteresisOptions* target = nullptr;
    for (const auto& [name, options] : rules) target = key == name ? options : target;
    if (!target) return alerts->Error(key, "unknown alert rule");
    Result<io::JsonFields> rule = alerts->Object(key);
    if (!rule.ok()) return rule.status();
    const std::pair<const char*, double*> members[] = {{"raise_above", &target->raise_above},
                                                       {"clear_below", &target->clear_below},
                                                       {"raise_after_s", &target->raise_after_s},
                                                       {"clear_after_s", &target->clear_after_s}};
    for (const auto& [member, unused] : value.items()) {
      bool known = false;
      for (const auto& [name, out] : members) known |= member == name;
      if (!known) return rule->Error(member, "unknown option");
    }
    for (const auto& [name, out] : members) {
      if (rule->Has(name)) FLEETLOC_RETURN_IF_ERROR(rule->Number(name, out));
    }
  }
  return Status::Ok();
}

// "http": every member of HttpLimits, optional; "allowed_hosts" a list of strings.
Status ReadHttp(const io::JsonFields& fields, const nlohmann::json& json, HttpLimits* h) {
  Result<io::JsonFields> http = fields.Object("http");
  if (!http.ok()) return http.status();
  const std::pair<const char*, int*> ints[] = {
      {"max_connections", &h->max_connections},
      {"max_connections_per_address", &h->max_connections_per_address},
      {"max_streams", &h->max_streams},
      {"workers", &h->workers},
      {"queue", &h->queue},
      {"max_requests_per_connection", &h->max_requests_per_connection},
      {"max_header_bytes", &h->max_header_bytes},
      {"max_header_count", &h->max_header_count},
      {"max_body_bytes", &h->max_body_bytes},
      {"max_ranges", &h->max_ranges},
      {"max_buffered_mb", &h->max_buffered_mb},
      {"auth_free_failures", &h->auth_free_failures}};
  const std::pair<const char*, double*> numbers[] = {
      {"header_timeout_s", &h->header_timeout_s},
      {"keep_alive_timeout_s", &h->keep_alive_timeout_s},
      {"write_timeout_s", &h->write_timeout_s},
      {"stream_keep_alive_s", &h->stream_keep_alive_s},
      {"auth_max_backoff_s", &h->auth_max_backoff_s}};
  for (const auto& [key, value] : json.items()) {
    bool known = key == "allowed_hosts";
    for (const auto& [name, out] : ints) known |= key == name;
    for (const auto& [name, out] : numbers) known |= key == name;
    if (!known) return http->Error(key, "unknown option");
  }
  for (const auto& [name, out] : ints) {  // ranges: Validate()
    if (!http->Has(name)) continue;
    double value = 0;
    FLEETLOC_RETURN_IF_ERROR(http->NonNegativeNumber(name, &value));
    if (value != static_cast<int>(value)) return http->Error(name, "must be an integer");
    *out = static_cast<int>(value);
  }
  for (const auto& [name, out] : numbers) {
    if (http->Has(name)) FLEETLOC_RETURN_IF_ERROR(http->PositiveNumber(name, out));
  }
  if (http->Has("allowed_hosts")) {
    const nlohmann::json& hosts = json["allowed_hosts"];
    if (!hosts.is_array()) return http->Error("allowed_hosts", "must be a list of host names");
    h->allowed_hosts.clear();
    for (const nlohmann::json& host : hosts) {
      if (!host.is_string()) return http->Error("allowed_hosts", "must be a list of host names");
      h->allowed_hosts.push_back(host.get<std::string>());
    }
  }
  return Status::Ok();
}

Status ReadTrail(const io::JsonFields& fields, const nlohmann::json& json, fleet::TrailOptions* t) {
  Result<io::JsonFields> trail = fields.Object("trail");
  if (!trail.ok()) return trail.status();
  for (const auto& [key, value] : json.items()) {
    if (key != "period_s" && key != "length_s") return trail->Error(key, "unknown option");
  }
  if (trail->Has("period_s"))
    FLEETLOC_RETURN_IF_ERROR(trail->PositiveNumber("period_s", &t->period_s));
  if (trail->Has("length_s"))
    FLEETLOC_RETURN_IF_ERROR(trail->PositiveNumber("length_s", &t->length_s));
  return Status::Ok();
}

}  // namespace

Result<SupervisorConfig> LoadSupervisorConfig(const std::string& path) {
  Result<nlohmann::json> json = io::ReadJsonObjectFile(path);
  if (!json.ok()) return json.status();
  const io::JsonFields fields(*json, path);
  SupervisorConfig c;
  const std::pair<const char*, std::string*> strings[] = {
      {"supervisor_id", &c.supervisor_id},
      {"dds_config", &c.dds_config_path},
      {"http_bind", &c.http_bind},
      {"port_file", &c.port_file},
      {"maintainer_token", &c.maintainer_token},
      {"maintainer_token_file", &c.maintainer_token_file},
      {"history_db", &c.history_db},
      {"web_dir", &c.web_dir},
      {"js_dir", &c.js_dir},
      {"mosaic_name", &c.mosaic_name}};
  const std::pair<const char*, int*> ints[] = {{"domain", &c.domain_id},
                                               {"http_port", &c.http_port},
                                               {"max_history_points", &c.max_history_points},
                                               {"tile_cache_mb", &c.tile_cache_mb},
                                               {"min_tile_level", &c.min_tile_level}};
  const std::pair<const char*, double*> numbers[] = {{"retention_s", &c.retention_s},
                                                     {"history_period_s", &c.history_period_s},
                                                     {"max_query_range_s", &c.max_query_range_s},
                                                     {"stream_period_s", &c.stream_period_s},
                                                     {"tile_timeout_s", &c.tile_timeout_s},
                                                     {"health_period_s", &c.health_period_s}};
  for (const auto& [key, value] : json->items()) {
    bool known =
        key == "alerts" || key == "trail" || key == "http" || key == "metrics" || key == "vda5050";
    for (const auto& [name, out] : strings) known |= key == name;
    for (const auto& [name, out] : ints) known |= key == name;
    for (const auto& [name, out] : numbers) known |= key == name;
    if (!known) return fields.Error(key, "unknown option");
  }
  for (const auto& [name, out] : strings) {
    if (fields.Has(name)) FLEETLOC_RETURN_IF_ERROR(fields.NonEmptyString(name, out));
  }
  for (const auto& [name, out] : ints) {  // ranges: Validate()
    if (!fields.Has(name)) continue;
    double value = 0;
    FLEETLOC_RETURN_IF_ERROR(fields.NonNegativeNumber(name, &value));
    if (value != static_cast<int>(value)) return fields.Error(name, "must be an integer");
    *out = static_cast<int>(value);
  }
  for (const auto& [name, out] : numbers) {
    if (fields.Has(name)) FLEETLOC_RETURN_IF_ERROR(fields.PositiveNumber(name, out));
  }
  if (fields.Has("alerts"))
    FLEETLOC_RETURN_IF_ERROR(ReadAlerts(fields, (*json)["alerts"], &c.alerts));
  if (fields.Has("trail")) FLEETLOC_RETURN_IF_ERROR(ReadTrail(fields, (*json)["trail"], &c.trail));
  if (fields.Has("http")) FLEETLOC_RETURN_IF_ERROR(ReadHttp(fields, (*json)["http"], &c.http));
  if (fields.Has("metrics"))
    FLEETLOC_RETURN_IF_ERROR(metrics::ReadMetricsOptions(fields, *json, &c.metrics));
  if (fields.Has("vda5050"))
    FLEETLOC_RETURN_IF_ERROR(ReadVda5050Options(fields, *json, &c.vda5050));
  if (Status valid = Validate(c); !valid.ok()) return InvalidInput(path + ": " + valid.message());
  return c;
}

namespace {

// "" or what makes `token` unfit to guard re-mapping.
std::string TokenProblem(const std::string& token) {
  if (token.size() < 16) return "the maintainer token is shorter than 16 characters";
  if (token.size() > 1024) return "the maintainer token is longer than 1024 characters";
  for (const char ch : token) {
    if (ch <= ' ' || ch > '~')
      return "the maintainer token has a character that is not printable ASCII";
  }
  return "";
}

// The token file must be a regular file nobody but its owner may read or write.
Status CheckTokenFileMode(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    return NotFound(path + ": cannot read the maintainer token file");
  if (!S_ISREG(st.st_mode))
    return InvalidInput(path + ": the maintainer token file is not a regular file");
  if ((st.st_mode & 077) != 0) {
    char mode[8];
    std::snprintf(mode, sizeof mode, "%03o", static_cast<unsigned>(st.st_mode & 0777));
    return InvalidInput(path + ": the maintainer token file has mode " + mode +
                        "; group and others must have no access (chmod 600)");
  }
  return Status::Ok();
}

}  // namespace

Result<std::string> ResolveMaintainerToken(const SupervisorConfig& c) {
  if (!c.maintainer_token.empty()) {
    if (const std::string problem = TokenProblem(c.maintainer_token); !problem.empty()) {
      return InvalidInput("fleet supervisor config: field 'maintainer_token': " + problem);
    }
    return c.maintainer_token;
  }
  if (c.maintainer_token_file.empty()) return std::string();
  FLEETLOC_RETURN_IF_ERROR(CheckTokenFileMode(c.maintainer_token_file));
  Result<std::string> text = io::ReadFileText(c.maintainer_token_file);
  if (!text.ok()) return text.status();
  std::string token = text->substr(0, text->find('\n'));
  while (!token.empty() && (token.back() == '\r' || token.back() == ' ')) token.pop_back();
  if (token.empty())
    return InvalidInput(c.maintainer_token_file + ": the maintainer token is empty");
  if (const std::string problem = TokenProblem(token); !problem.empty()) {
    return InvalidInput(c.maintainer_token_file + ": " + problem);
  }
  return token;
}

}  // namespace fleetloc::fleet_supervisor
