// The supervisor's HTTP server (cpp-httplib behind the connection front: guarded_server.h): the
// JSON API, the live stream (Server-Sent Events, served by the stream hub) and the dashboard's
// static files. Reads are open; every change (starting a re-mapping job) needs the maintainer
// token as "Authorization: Bearer <token>" — 401 without it, 403 with a wrong one or when no token
// is configured (read-only), 429 while the client must wait after repeated wrong tokens
// (auth_throttle.h). GET /healthz answers 200 while the process serves HTTP; GET /readyz 200 when
// every readiness check holds, else 503 naming the failing ones. Bad input gets a 4xx JSON
// {"error": "..."} and is counted. The API is listed in docs/architecture.md; what a client may
// cost the server, in http_limits.h.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <thread>

#include "base/status.h"
#include "fleet_supervisor/auth_throttle.h"
#include "fleet_supervisor/event_stream.h"
#include "fleet_supervisor/history_store.h"
#include "fleet_supervisor/overview_tiles.h"
#include "fleet_supervisor/shared_fleet.h"
#include "fleet_supervisor/supervisor_config.h"
#include "fleet_supervisor/supervisor_view.h"
#include "transport/remap_client.h"

namespace httplib {
struct Request;
struct Response;
}  // namespace httplib

namespace fleetloc::fleet_supervisor {

class GuardedServer;

// What the handlers use; everything outlives the HttpApi.
struct ApiContext {
  const SupervisorConfig* config = nullptr;
  std::string maintainer_token;  // empty: read-only
  SharedFleet* fleet = nullptr;
  HistoryStore* history = nullptr;
  OverviewTiles* tiles = nullptr;
  EventStream* stream = nullptr;
  // Sends a RemapCommand; Unavailable-like Internal when no map server listens.
  std::function<Result<uint64_t>(const transport::RemapRequest&)> start_remap;
  std::function<bool()> map_server_listening;
  // The conditions GET /readyz reports (see fleet_supervisor.cpp); none: ready once serving.
  std::function<std::vector<ReadinessCheck>()> readiness;
};

class HttpApi {
 public:
  explicit HttpApi(ApiContext context);
  ~HttpApi();  // stops the server

  // Binds (config http_bind / http_port; port 0: any free one) and serves `web_dir` at "/" on a
  // thread of its own. Internal naming the address if it cannot bind.
  Status Start(const std::string& web_dir);
  int port() const { return port_; }
  void Stop();

 private:
  using Request = httplib::Request;
  using Response = httplib::Response;

  // http_routes.cpp: the hooks (counting, JSON errors) and one handler per route of api_routes.h.
  void Hooks();
  void Routes();
  // A vehicle id from the path (false, answered: 400 malformed, 404 unknown).
  bool VehicleId(const Request& req, Response& res, std::string* id);
  // The maintainer token of a change request (false, answered: 401, 403 or 429).
  bool Authorized(const Request& req, Response& res);
  void GetOpenApi(const Request& req, Response& res);
  void GetHealthz(const Request& req, Response& res);
  void GetReadyz(const Request& req, Response& res);
  void GetFleet(const Request& req, Response& res);
  void GetVehicle(const Request& req, Response& res);
  void GetVehicleHistory(const Request& req, Response& res);
  void GetAlerts(const Request& req, Response& res);
  void GetMosaic(const Request& req, Response& res);
  void GetTile(const Request& req, Response& res);
  void GetRemapJobs(const Request& req, Response& res);
  void PostRemap(const Request& req, Response& res);
  void GetAuth(const Request& req, Response& res);
  void GetStats(const Request& req, Response& res);

  ApiContext ctx_;
  AuthThrottle throttle_;
  std::unique_ptr<GuardedServer> server_;
  std::thread thread_;
  int port_ = 0;
};

}  // namespace fleetloc::fleet_supervisor
