// HttpApi: the server's life (binding, the dashboard's static files, starting and stopping); the
// routes and their handlers are in http_routes.cpp.
#include "fleet_supervisor/http_api.h"  // Eigen before httplib (see guarded_server.h)

#include <httplib.h>
#include <spdlog/spdlog.h>

#include <cctype>
#include <cerrno>
#include <cstring>

#include "fleet_supervisor/guarded_server.h"
#include "io/file_util.h"

namespace fleetloc::fleet_supervisor {

namespace {

// What the connection front checks, from the configuration.
RequestPolicy PolicyOf(const SupervisorConfig& c) {
  RequestPolicy policy;
  policy.allowed_hosts =
      c.http.allowed_hosts.empty() ? DefaultAllowedHosts(c.http_bind) : c.http.allowed_hosts;
  for (std::string& host : policy.allowed_hosts) {
    for (char& ch : host) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  }
  policy.max_ranges = c.http.max_ranges;
  policy.max_body_bytes = static_cast<size_t>(c.http.max_body_bytes);
  return policy;
}

ThrottleOptions ThrottleOf(const SupervisorConfig& c) {
  ThrottleOptions o;
  o.free_failures = c.http.auth_free_failures;
  o.max_backoff_s = c.http.auth_max_backoff_s;
  return o;
}

}  // namespace

HttpApi::HttpApi(ApiContext context)
    : ctx_(std::move(context)),
      throttle_(ThrottleOf(*ctx_.config)),
      server_(std::make_unique<GuardedServer>(ctx_.config->http, PolicyOf(*ctx_.config),
                                              ctx_.stream, &ctx_.fleet->counters())) {}

HttpApi::~HttpApi() { Stop(); }

void HttpApi::Stop() {
  if (ctx_.stream) ctx_.stream->Close();
  if (server_) server_->stop();
  if (thread_.joinable()) thread_.join();
  if (server_) server_->StopGuards();
}

namespace {

// The dashboard's libraries from the system's packages (libjs-leaflet, libjs-chart.js): served
// from there, not copied into the project, so security updates reach them. Without them the
// dashboard still shows the fleet, without its map and plots (warned).
void MountVendorLibraries(GuardedServer& s, const std::string& js_dir) {
  struct Library {
    const char* name;
    const char* package;
    const char* gives;
  };
  for (const Library& l : {Library{"leaflet", "libjs-leaflet", "map"},
                           Library{"chart.js", "libjs-chart.js", "plots"}}) {
    const std::string dir = js_dir + "/" + l.name;
    if (!s.set_mount_point(std::string("/vendor/") + l.name, dir)) {
      spdlog::warn("{}: missing (install {}): the dashboard has no {}", dir, l.package, l.gives);
    }
  }
}

}  // namespace

Status HttpApi::Start(const std::string& web_dir) {
  GuardedServer& s = *server_;
  s.set_payload_max_length(
      static_cast<size_t>(ctx_.config->http.max_body_bytes));  // the front checks first
  if (!s.set_mount_point("/", web_dir))
    return NotFound(web_dir + ": the dashboard's web directory is missing");
  MountVendorLibraries(s, ctx_.config->js_dir);
  Routes();
  const SupervisorConfig& c = *ctx_.config;
  int error = 0;
  port_ = s.Bind(c.http_bind, c.http_port, &error);
  if (port_ <= 0) {
    const std::string why = error == EADDRINUSE
                                ? "the port is in use (another supervisor or service listens there)"
                            : error != 0 ? std::strerror(error)
                                         : "cannot bind";
    return Internal("cannot listen on " + c.http_bind + ":" + std::to_string(c.http_port) + ": " +
                    why);
  }
  const long files = io::RaiseOpenFileLimit();
  const long needed = static_cast<long>(c.http.max_connections) + c.http.max_streams + 256;
  if (files < needed) {
    spdlog::warn(
        "open-file limit {} is below the {} that http.max_connections and max_streams may "
        "need: raise LimitNOFILE (beyond it new connections wait to be accepted)",
        files, needed);
  }
  FLEETLOC_RETURN_IF_ERROR(s.StartGuards());
  thread_ = std::thread([this] { server_->listen_after_bind(); });
  spdlog::info(
      "dashboard on http://{}:{}/ ({})", c.http_bind, port_,
      ctx_.maintainer_token.empty() ? "read-only: no maintainer token" : "maintainer token set");
  return Status::Ok();
}

}  // namespace fleetloc::fleet_supervisor
