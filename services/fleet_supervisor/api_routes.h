// Every path the supervisor's HTTP server answers, with its method: the one table HttpApi
// registers its handlers from (a handler for a route missing here, or a route here without a
// handler, aborts at start) and that the tests compare with the OpenAPI description
// (openapi.json, served at /api/openapi.json).
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace fleetloc::fleet_supervisor {

struct ApiRoute {
  const char* method;   // "GET", "POST"
  const char* path;     // as in the OpenAPI document: "/api/vehicles/{vehicle_id}"
  const char* pattern;  // the regex httplib matches; "" when answered outside httplib's routes
                        // (the live stream by the stream hub, the dashboard by the static mount)
};

const std::vector<ApiRoute>& ApiRoutes();

// The pattern of the route (method, path); aborts when the table has no such route (a programming
// error: a handler registered for an undocumented path).
const char* RoutePattern(std::string_view method, std::string_view path);

// The OpenAPI 3 description (openapi.json, embedded at build time).
std::string_view OpenApiDocument();

}  // namespace fleetloc::fleet_supervisor
