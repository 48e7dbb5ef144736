// HttpApi's routes: one handler per route of the route table (api_routes.h), the checks of the
// requests' input (vehicle ids, query parameters, the maintainer token) and the server's hooks.
// clang-format off: Eigen before httplib (<resolv.h> defines `_res`, a name Eigen's headers use)
#include <Eigen/Core>
// clang-format on
#include <httplib.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdlib>

#include "fleet_link/fleet_view.h"
#include "fleet_supervisor/api_routes.h"
#include "fleet_supervisor/guarded_server.h"
#include "fleet_supervisor/http_api.h"  // Eigen before httplib (see guarded_server.h)
#include "fleet_supervisor/supervisor_view.h"
#include "io/json_fields.h"
#include "transport/wire_util.h"

namespace fleetloc::fleet_supervisor {

using httplib::Request;
using httplib::Response;
using nlohmann::json;

namespace {

constexpr int kMaxHistoryRows = 200000;  // rows read for one series before thinning
constexpr double kDefaultHistoryS = 600;
constexpr int kDefaultHistoryPoints = 500;

double Now() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

void Reply(Response& res, int status, const json& body) {
  res.status = status;
  res.set_content(io::DumpJson(body), "application/json");
}

void Fail(Response& res, int status, const std::string& message) {
  Reply(res, status, {{"error", message}});
}

// Strict parsing: the whole text must be the number.
bool ParseInt(const std::string& text, long long* out) {
  const char* end = text.data() + text.size();
  auto [ptr, ec] = std::from_chars(text.data(), end, *out);
  return ec == std::errc() && ptr == end && !text.empty();
}
bool ParseDouble(const std::string& text, double* out) {
  const char* end = text.data() + text.size();
  auto [ptr, ec] = std::from_chars(text.data(), end, *out);
  return ec == std::errc() && ptr == end && !text.empty() && std::isfinite(*out);
}

// The query parameter `name` as a number; `fallback` when absent. False (with a 400 sent) when
// present but not a number.
bool NumberParam(const Request& req, Response& res, const char* name, double fallback,
                 double* out) {
  *out = fallback;
  if (!req.has_param(name)) return true;
  if (ParseDouble(req.get_param_value(name), out)) return true;
  Fail(res, 400, std::string("query parameter '") + name + "' must be a finite number");
  return false;
}

// Constant-time comparison, so a wrong token's timing tells nothing about the right one.
bool SameToken(const std::string& a, const std::string& b) {
  unsigned char diff = a.size() == b.size() ? 0 : 1;
  for (size_t i = 0; i < a.size(); ++i)
    diff |= static_cast<unsigned char>(a[i] ^ b[i % std::max<size_t>(b.size(), 1)]);
  return diff == 0;
}

double SteadyNow() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace

// The server's hooks: every answer counted (4xx as rejected), errors and exceptions as JSON.
void HttpApi::Hooks() {
  httplib::Server& s = *server_;
  SharedFleet& fleet = *ctx_.fleet;
  s.set_logger([&fleet](const Request&, const Response& res) {
    ++fleet.counters().http_requests;
    if (res.status >= 400 && res.status < 500) ++fleet.counters().http_rejected;
  });
  s.set_error_handler([](const Request& req, Response& res) {
    if (res.body.empty()) {
      Fail(res, res.status,
           res.status == 404 ? "no such resource: " + req.path
                             : "request failed (HTTP " + std::to_string(res.status) + ")");
    }
  });
  s.set_exception_handler(
      [](const Request&, Response& res, std::exception_ptr) { Fail(res, 500, "internal error"); });
}

void HttpApi::Routes() {
  Hooks();
  // Every handler's path comes from the route table (api_routes.h), which the OpenAPI description
  // documents; the handlers are counted so that a table entry without a handler is caught too.
  using Handler = void (HttpApi::*)(const Request&, Response&);
  struct Route {
    const char* method;
    const char* path;
    Handler handle;
  };
  static constexpr Route kRoutes[] = {
      {"GET", "/api/openapi.json", &HttpApi::GetOpenApi},
      {"GET", "/healthz", &HttpApi::GetHealthz},
      {"GET", "/readyz", &HttpApi::GetReadyz},
      {"GET", "/api/fleet", &HttpApi::GetFleet},
      {"GET", "/api/vehicles/{vehicle_id}", &HttpApi::GetVehicle},
      {"GET", "/api/vehicles/{vehicle_id}/history", &HttpApi::GetVehicleHistory},
      {"GET", "/api/alerts", &HttpApi::GetAlerts},
      {"GET", "/api/mosaic", &HttpApi::GetMosaic},
      {"GET", "/api/tiles/{level}/{col}/{row}.png", &HttpApi::GetTile},
      {"GET", "/api/remap", &HttpApi::GetRemapJobs},
      {"POST", "/api/remap", &HttpApi::PostRemap},
      {"GET", "/api/auth", &HttpApi::GetAuth},
      {"GET", "/api/stats", &HttpApi::GetStats},
  };
  httplib::Server& s = *server_;
  size_t registered = 0;
  for (const Route& r : kRoutes) {
    ++registered;
    const char* pattern = RoutePattern(r.method, r.path);
    auto handler = [this, handle = r.handle](const Request& req, Response& res) {
      (this->*handle)(req, res);
    };
    if (std::string_view(r.method) == "POST") {
      s.Post(pattern, handler);
    } else {
      s.Get(pattern, handler);
    }
  }
  // GET /api/events never reaches here: the connection front hands it to the stream hub; "/" and
  // "/{file}" are the static mount (Start).
  size_t expected = 0;
  for (const ApiRoute& r : ApiRoutes()) expected += std::string(r.pattern).empty() ? 0 : 1;
  if (registered != expected) {
    spdlog::critical("HttpApi: {} handlers for {} routes in api_routes.cpp", registered, expected);
    std::abort();
  }
}

// A vehicle id from the path: 400 if malformed, 404 if the supervisor never heard of it.
bool HttpApi::VehicleId(const Request& req, Response& res, std::string* id) {
  *id = req.matches[1];
  if (!transport::IsValidEntityId(*id)) {
    Fail(res, 400, "vehicle id '" + id->substr(0, 32) + "' is not 1-11 of [A-Za-z0-9_-]");
    return false;
  }
  if (ctx_.fleet->Vehicle(*id)) return true;
  Result<bool> known = ctx_.history->KnowsVehicle(*id);
  if (known.ok() && *known) return true;
  Fail(res, 404, "unknown vehicle '" + *id + "'");
  return false;
}

// The maintainer token of a change request: 401 without one, 403 when wrong or read-only.
// After a few wrong tokens a client must wait longer and longer before its token is checked.
bool HttpApi::Authorized(const Request& req, Response& res) {
  const std::string header = req.get_header_value("Authorization");
  if (ctx_.maintainer_token.empty()) {
    Fail(res, 403, "read-only: this supervisor has no maintainer token configured");
    return false;
  }
  if (header.rfind("Bearer ", 0) != 0) {
    res.set_header("WWW-Authenticate", "Bearer");
    Fail(res, 401, "a maintainer token is required (Authorization: Bearer <token>)");
    return false;
  }
  if (const double wait = throttle_.RetryAfter(req.remote_addr, SteadyNow()); wait > 0) {
    ++ctx_.fleet->counters().http_auth_throttled;
    res.set_header("Retry-After", std::to_string(static_cast<long long>(std::ceil(wait))));
    Fail(res, 429,
         "too many wrong maintainer tokens: try again in " +
             std::to_string(static_cast<long long>(std::ceil(wait))) + " s");
    return false;
  }
  if (!SameToken(header.substr(7), ctx_.maintainer_token)) {
    throttle_.Failed(req.remote_addr, SteadyNow());
    spdlog::warn("wrong maintainer token from {}", req.remote_addr);
    Fail(res, 403, "wrong maintainer token");
    return false;
  }
  throttle_.Succeeded(req.remote_addr);
  return true;
}

void HttpApi::GetOpenApi(const Request&, Response& res) {
  res.set_content(OpenApiDocument().data(), OpenApiDocument().size(), "application/json");
}

void HttpApi::GetHealthz(const Request&, Response& res) { Reply(res, 200, {{"alive", true}}); }

void HttpApi::GetReadyz(const Request&, Response& res) {
  bool ready = true;
  const json body =
      ReadinessJson(ctx_.readiness ? ctx_.readiness() : std::vector<ReadinessCheck>{}, &ready);
  Reply(res, ready ? 200 : 503, body);
}

void HttpApi::GetFleet(const Request& req, Response& res) {
  Reply(res, 200, ctx_.fleet->Fleet(Now(), req.get_param_value("trails") == "1"));
}

void HttpApi::GetVehicle(const Request& req, Response& res) {
  std::string id;
  if (!VehicleId(req, res, &id)) return;
  Reply(res, 200,
        ctx_.fleet->Vehicle(id).value_or(json{{"id", id}, {"silent", true}, {"pose", nullptr}}));
}

void HttpApi::GetVehicleHistory(const Request& req, Response& res) {
  const SupervisorConfig& config = *ctx_.config;
  std::string id;
  if (!VehicleId(req, res, &id)) return;
  double to = 0, from = 0, points = 0;
  if (!NumberParam(req, res, "to", Now(), &to) ||
      !NumberParam(req, res, "from", to - kDefaultHistoryS, &from) ||
      !NumberParam(req, res, "max_points", kDefaultHistoryPoints, &points)) {
    return;
  }
  if (from > to) return Fail(res, 400, "'from' is after 'to'");
  if (to - from > config.max_query_range_s) {
    return Fail(res, 400,
                "query range of " + std::to_string(static_cast<long long>(to - from)) +
                    " s exceeds the limit of " +
                    std::to_string(static_cast<long long>(config.max_query_range_s)) + " s");
  }
  if (points != std::floor(points) || points < 2 || points > config.max_history_points) {
    return Fail(res, 400,
                "'max_points' must be an integer in [2, " +
                    std::to_string(config.max_history_points) + "]");
  }
  auto poses = ctx_.history->Poses(id, from, to, kMaxHistoryRows);
  auto health = ctx_.history->Health(id, from, to, kMaxHistoryRows);
  if (!poses.ok() || !health.ok()) return Fail(res, 500, "history unavailable");
  const size_t n = static_cast<size_t>(points);
  Reply(res, 200,
        {{"vehicle", id},
         {"from", from},
         {"to", to},
         {"poses", PoseHistoryJson(*poses, n)},
         {"health", HealthHistoryJson(*health, n)}});
}

void HttpApi::GetAlerts(const Request& req, Response& res) {
  AlertQuery q;
  q.active_only = req.get_param_value("active") == "1";
  q.vehicle_id = req.get_param_value("vehicle");
  long long limit = 200;
  if (req.has_param("limit") &&
      (!ParseInt(req.get_param_value("limit"), &limit) || limit < 1 || limit > 10000)) {
    return Fail(res, 400, "'limit' must be an integer in [1, 10000]");
  }
  if (!q.vehicle_id.empty() && !transport::IsValidEntityId(q.vehicle_id)) {
    return Fail(res, 400, "'vehicle' is not 1-11 of [A-Za-z0-9_-]");
  }
  q.limit = static_cast<int>(limit);
  auto alerts = ctx_.history->Alerts(q);
  if (!alerts.ok()) return Fail(res, 500, "history unavailable");
  json list = json::array();
  for (const fleet::Alert& a : *alerts) list.push_back(fleet_link::AlertJson(a));
  Reply(res, 200, {{"active", ctx_.fleet->ActiveAlerts()}, {"history", std::move(list)}});
}

void HttpApi::GetMosaic(const Request&, Response& res) {
  std::optional<mosaic::MosaicLayout> layout = ctx_.tiles->Layout();
  if (!layout) return Fail(res, 503, "no map server has announced a mosaic yet");
  const std::string& name = ctx_.config->mosaic_name;
  Reply(res, 200,
        {{"mosaic_id", layout->mosaic_id},
         {"version", layout->version},
         {"name", name.empty() ? "floor" : name},
         {"width_px", layout->width_px},
         {"height_px", layout->height_px},
         {"tile_size_px", layout->tile_size_px},
         {"levels", layout->levels},
         {"origin_x", layout->geo.origin_x},
         {"origin_y", layout->geo.origin_y},
         {"resolution", layout->geo.resolution},
         {"min_level", ctx_.config->min_tile_level}});
}

void HttpApi::GetTile(const Request& req, Response& res) {
  long long v[3];
  for (int i = 0; i < 3; ++i) {
    if (!ParseInt(req.matches[i + 1], &v[i]) || v[i] < 0 || v[i] > (1 << 24)) {
      return Fail(res, 400,
                  "tile address must be /api/tiles/LEVEL/COL/ROW.png with non-negative integers");
    }
  }
  const TileAnswer answer =
      ctx_.tiles->Get({static_cast<int>(v[0]), static_cast<int>(v[1]), static_cast<int>(v[2])});
  using Outcome = TileAnswer::Outcome;
  switch (answer.outcome) {
    case Outcome::kOk:
      ++ctx_.fleet->counters().tiles_served;
      res.set_header("Cache-Control", "max-age=3600");
      res.set_header("X-Mosaic-Version", std::to_string(answer.version));
      res.set_content(reinterpret_cast<const char*>(answer.png->data()), answer.png->size(),
                      "image/png");
      return;
    case Outcome::kOutOfRange:
      return Fail(res, 404, answer.error);
    case Outcome::kNoMosaic:
      return Fail(res, 503, answer.error);
    case Outcome::kTimeout:
      return Fail(res, 504, answer.error);
    case Outcome::kError:
      return Fail(res, 502, answer.error);
  }
}

void HttpApi::GetRemapJobs(const Request&, Response& res) {
  Reply(res, 200, {{"jobs", ctx_.fleet->RemapJobs()}});
}

void HttpApi::PostRemap(const Request& req, Response& res) {
  if (!Authorized(req, res)) return;
  const json body = json::parse(req.body, nullptr, false);
  if (body.is_discarded() || !body.is_object())
    return Fail(res, 400, "the body must be a JSON object");
  for (const auto& [key, value] : body.items()) {
    if (key != "region" && key != "mode")
      return Fail(res, 400, "unknown key '" + key + "' (known: region, mode)");
  }
  const auto region = body.find("region");
  if (region == body.end() || !region->is_array() || region->size() != 4 ||
      !std::all_of(region->begin(), region->end(), [](const json& v) { return v.is_number(); })) {
    return Fail(res, 400, "'region' must be [x_min, y_min, x_max, y_max] in map metres");
  }
  const std::string mode = body.value("mode", "blend");
  if (mode != "blend" && mode != "replace")
    return Fail(res, 400, "'mode' must be 'blend' or 'replace'");
  transport::RemapRequest request{(*region)[0],
                                  (*region)[1],
                                  (*region)[2],
                                  (*region)[3],
                                  mode == "replace",
                                  "",
                                  "dashboard:" + ctx_.config->supervisor_id};
  if (!ctx_.map_server_listening())
    return Fail(res, 503, "no map server is listening for re-mapping commands");
  Result<uint64_t> id = ctx_.start_remap(request);
  if (!id.ok())
    return Fail(res, id.status().code() == StatusCode::kInvalidInput ? 400 : 502,
                id.status().message());
  ++ctx_.fleet->counters().remaps_started;
  spdlog::info("remap {} started from the dashboard: [{}, {}, {}, {}] {}", *id, request.x_min,
               request.y_min, request.x_max, request.y_max, mode);
  Reply(res, 202, {{"command_id", std::to_string(*id)}});
}

void HttpApi::GetAuth(const Request& req, Response& res) {
  if (Authorized(req, res)) Reply(res, 200, {{"maintainer", true}});
}

void HttpApi::GetStats(const Request&, Response& res) {
  json counters;
  for (const auto& [name, value] : ctx_.fleet->counters().Snapshot()) counters[name] = value;
  Reply(res, 200, counters);
}

}  // namespace fleetloc::fleet_supervisor
