// The route table against the embedded OpenAPI description: the same (method, path) pairs, each
// route's pattern matching its documented path with the documented example parameters, and the
// embedded copy equal to openapi.json in the source tree.
#include "fleet_supervisor/api_routes.h"

#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <sstream>

namespace fleetloc::fleet_supervisor {
namespace {

using nlohmann::json;

json Document() {
  const json doc = json::parse(OpenApiDocument(), nullptr, false);
  EXPECT_FALSE(doc.is_discarded()) << "the embedded OpenAPI document is not JSON";
  return doc;
}

// `path` with each {param} replaced by the example of that path parameter.
std::string Example(const std::string& path, const json& operation) {
  std::string out = path;
  for (const json& p : operation.value("parameters", json::array())) {
    if (p.value("in", "") != "path") continue;
    const std::string token = "{" + p["name"].get<std::string>() + "}";
    const json& example = p.at("example");
    const std::string value = example.is_string() ? example.get<std::string>() : example.dump();
    out.replace(out.find(token), token.size(), value);
  }
  return out;
}

TEST(ApiRoutes, TheTableAndTheOpenApiDocumentListTheSameRoutes) {
  const json doc = Document();
  EXPECT_EQ(doc.value("openapi", ""), "3.0.3");
  std::set<std::pair<std::string, std::string>> documented, table;
  for (const auto& [path, item] : doc.at("paths").items()) {
    for (const auto& [method, operation] : item.items()) {
      std::string upper = method;
      for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
      documented.insert({upper, path});
    }
  }
  for (const ApiRoute& r : ApiRoutes()) table.insert({r.method, r.path});
  EXPECT_EQ(documented, table);
}

TEST(ApiRoutes, EachPatternMatchesItsDocumentedExample) {
  const json doc = Document();
  for (const ApiRoute& r : ApiRoutes()) {
    if (std::string(r.pattern).empty()) continue;
    std::string method = r.method;
    for (char& c : method) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    const json& operation = doc.at("paths").at(r.path).at(method);
    const std::string example = Example(r.path, operation);
    EXPECT_TRUE(std::regex_match(example, std::regex(r.pattern))) << r.pattern << " vs " << example;
    for (const json& p : operation.value("parameters", json::array())) {
      EXPECT_TRUE(p.contains("example"))
          << r.path << ": parameter " << p.value("name", "") << " has no example";
    }
  }
}

TEST(ApiRoutes, TheEmbeddedDocumentIsTheSourceFile) {
  std::ifstream in(std::string(FLEETLOC_SOURCE_DIR) + "/services/fleet_supervisor/openapi.json");
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_EQ(json::parse(text.str()), Document());
}

TEST(ApiRoutesDeathTest, ARouteMissingFromTheTableIsAProgrammingError) {
  EXPECT_EQ(std::string(RoutePattern("GET", "/api/fleet")), "/api/fleet");
  EXPECT_DEATH(RoutePattern("DELETE", "/api/fleet"), "not in the route table");
}

}  // namespace
}  // namespace fleetloc::fleet_supervisor
