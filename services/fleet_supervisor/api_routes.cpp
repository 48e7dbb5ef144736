// The route table.
#include "fleet_supervisor/api_routes.h"

#include <cstdio>
#include <cstdlib>
#include <string>

namespace fleetloc::fleet_supervisor {

const std::vector<ApiRoute>& ApiRoutes() {
  static const std::vector<ApiRoute> routes = {
      {"GET", "/api/openapi.json", R"(/api/openapi\.json)"},
      {"GET", "/healthz", "/healthz"},
      {"GET", "/readyz", "/readyz"},
      {"GET", "/api/fleet", "/api/fleet"},
      {"GET", "/api/vehicles/{vehicle_id}", R"(/api/vehicles/([^/]+))"},
      {"GET", "/api/vehicles/{vehicle_id}/history", R"(/api/vehicles/([^/]+)/history)"},
      {"GET", "/api/alerts", "/api/alerts"},
      {"GET", "/api/mosaic", "/api/mosaic"},
      {"GET", "/api/tiles/{level}/{col}/{row}.png", R"(/api/tiles/([^/]+)/([^/]+)/([^/]+)\.png)"},
      {"GET", "/api/remap", "/api/remap"},
      {"POST", "/api/remap", "/api/remap"},
      {"GET", "/api/auth", "/api/auth"},
      {"GET", "/api/stats", "/api/stats"},
      {"GET", "/api/events", ""},  // the stream hub (connection_front.cpp)
      {"GET", "/", ""},            // the dashboard's static files (set_mount_point)
      {"GET", "/{file}", ""},
  };
  return routes;
}

const char* RoutePattern(std::string_view method, std::string_view path) {
  for (const ApiRoute& r : ApiRoutes()) {
    if (method == r.method && path == r.path) return r.pattern;
  }
  std::fprintf(stderr, "RoutePattern: %s %s is not in the route table (api_routes.cpp)\n",
               std::string(method).c_str(), std::string(path).c_str());
  std::abort();
}

}  // namespace fleetloc::fleet_supervisor
