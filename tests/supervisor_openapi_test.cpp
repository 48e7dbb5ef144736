// The supervisor's OpenAPI description against the live server (a map server, the supervisor and
// a vehicle on their own DDS domain): /api/openapi.json is the document in the source tree; every
// documented operation, called with its documented examples, answers with a documented status,
// content type and a body that fits the documented schema; documented error cases answer as
// described; and paths or methods the document does not list are refused (4xx).
// Eigen (through the fixtures) before httplib: <resolv.h> defines a macro that breaks Eigen.
// clang-format off: these first (Eigen before httplib, whose <resolv.h> defines `_res`).
#include "fake_vehicle.h"
#include "map_server_fixture.h"
#include "supervisor_fixture.h"
// clang-format on

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <httplib.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <nlohmann/json.hpp>
#include <regex>

namespace fleetloc {
namespace {

using nlohmann::json;
using testing::Eventually;
constexpr uint32_t kDomain = 122;
constexpr const char* kToken = "openapi-test-token-0123";

// Checks `value` against the OpenAPI schema subset the document uses ($ref, type, nullable,
// enum, required, properties, additionalProperties, items, minItems, maxItems, pattern);
// returns "" or what does not fit, at `where`.
std::string Misfit(const json& doc, const json& schema, const json& value,
                   const std::string& where) {
  if (schema.contains("$ref")) {
    const std::string ref = schema["$ref"];  // "#/components/schemas/X"
    return Misfit(doc, doc.at(json::json_pointer(ref.substr(1))), value, where);
  }
  if (value.is_null()) return schema.value("nullable", false) ? "" : where + ": null";
  const std::string type = schema.value("type", "");
  const bool fits =
      type.empty() || (type == "object" && value.is_object()) ||
      (type == "array" && value.is_array()) || (type == "string" && value.is_string()) ||
      (type == "boolean" && value.is_boolean()) ||
      (type == "integer" && value.is_number_integer()) || (type == "number" && value.is_number());
  if (!fits) return where + ": expected " + type + ", got " + value.dump().substr(0, 80);
  if (schema.contains("enum") &&
      std::find(schema["enum"].begin(), schema["enum"].end(), value) == schema["enum"].end()) {
    return where + ": " + value.dump() + " not in the enum";
  }
  if (schema.contains("pattern") &&
      !std::regex_search(value.get<std::string>(),
                         std::regex(schema["pattern"].get<std::string>()))) {
    return where + ": does not match the pattern";
  }
  if (value.is_array()) {
    if (value.size() < schema.value("minItems", 0u) ||
        value.size() > schema.value("maxItems", 1u << 30)) {
      return where + ": wrong number of items";
    }
    for (size_t i = 0; i < value.size() && schema.contains("items"); ++i) {
      if (std::string m =
              Misfit(doc, schema["items"], value[i], where + "[" + std::to_string(i) + "]");
          !m.empty())
        return m;
    }
  }
  if (value.is_object()) {
    for (const json& name : schema.value("required", json::array())) {
      if (!value.contains(name.get<std::string>()))
        return where + ": missing " + name.get<std::string>();
    }
    for (const auto& [key, member] : value.items()) {
      const json properties = schema.value("properties", json::object());
      const std::string at = std::string(where).append(".").append(key);
      if (properties.contains(key)) {
        if (std::string m = Misfit(doc, properties[key], member, at); !m.empty()) return m;
      } else if (schema.contains("additionalProperties") &&
                 schema["additionalProperties"].is_object()) {
        if (std::string m = Misfit(doc, schema["additionalProperties"], member, at); !m.empty())
          return m;
      }
    }
  }
  return "";
}

struct Answer {
  int status = -1;
  std::string content_type;
  std::string body;
};

// Sends a request by hand and reads until the connection closes or, for a stream, until the
// first event ("data:") arrived.
Answer Raw(int port, const std::string& method, const std::string& target,
           const httplib::Headers& headers, const std::string& body) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<uint16_t>(port));
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  Answer a;
  if (::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
    ::close(fd);
    return a;
  }
  std::string request =
      method + " " + target + " HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n";
  for (const auto& [k, v] : headers) request.append(k).append(": ").append(v).append("\r\n");
  if (!body.empty() || method == "POST") {
    request +=
        "Content-Type: application/json\r\nContent-Length: " + std::to_string(body.size()) + "\r\n";
  }
  request += "\r\n" + body;
  (void)::write(fd, request.data(), request.size());
  std::string text;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  char buffer[8192];
  while (std::chrono::steady_clock::now() < deadline) {
    pollfd p{fd, POLLIN, 0};
    if (::poll(&p, 1, 100) <= 0) continue;
    const ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n <= 0) break;
    text.append(buffer, static_cast<size_t>(n));
    const size_t head_end = text.find("\r\n\r\n");
    if (head_end != std::string::npos && text.find("text/event-stream") < head_end &&
        text.find("data:", head_end) != std::string::npos) {
      break;
    }
  }
  ::close(fd);
  const size_t head_end = text.find("\r\n\r\n");
  if (text.rfind("HTTP/1.1 ", 0) != 0 || head_end == std::string::npos) return a;
  a.status = std::stoi(text.substr(9, 3));
  std::smatch type;
  const std::string head = text.substr(0, head_end);
  if (std::regex_search(head, type, std::regex("\r\n[Cc]ontent-[Tt]ype: ([^;\r]+)")))
    a.content_type = type[1];
  a.body = text.substr(head_end + 4);
  const std::regex chunked("\r\n[Tt]ransfer-[Ee]ncoding: chunked");
  if (std::regex_search(head, chunked)) {  // de-chunk
    std::string plain;
    size_t at = 0;
    while (at < a.body.size()) {
      const size_t line = a.body.find("\r\n", at);
      if (line == std::string::npos) break;
      const size_t n = std::stoul(a.body.substr(at, line - at), nullptr, 16);
      if (n == 0) break;
      plain += a.body.substr(line + 2, n);
      at = line + 2 + n + 2;
    }
    a.body = plain;
  }
  return a;
}

// The documented operation's target with every parameter's example filled in.
std::string Target(const std::string& path, const json& operation) {
  std::string target = path, query;
  for (const json& p : operation.value("parameters", json::array())) {
    const json& example = p.at("example");
    const std::string value = example.is_string() ? example.get<std::string>() : example.dump();
    const std::string name = p["name"];
    if (p["in"] == "path") target.replace(target.find("{" + name + "}"), name.size() + 2, value);
    if (p["in"] == "query")
      query.append(query.empty() ? "?" : "&").append(name).append("=").append(value);
  }
  return target + query;
}

class SupervisorOpenApi : public ::testing::Test {
 protected:
  // Checks `a` against the operation's documented responses; "" or what differs.
  std::string Described(const json& operation, const Answer& a, const std::string& what) {
    const json& responses = operation.at("responses");
    const std::string code = std::to_string(a.status);
    if (!responses.contains(code))
      return what + ": status " + code + " is not documented (" + a.body.substr(0, 200) + ")";
    json response = responses[code];
    if (response.contains("$ref"))
      response = doc_.at(json::json_pointer(response["$ref"].get<std::string>().substr(1)));
    if (!response.contains("content")) return "";
    if (!response["content"].contains(a.content_type))
      return what + ": content type '" + a.content_type + "' not documented for " + code;
    if (a.content_type != "application/json") return "";
    const json body = json::parse(a.body, nullptr, false);
    if (body.is_discarded()) return what + ": the body is not JSON";
    return Misfit(doc_, response["content"][a.content_type]["schema"], body, what);
  }

  json doc_;
};

TEST_F(SupervisorOpenApi, EveryDocumentedOperationAnswersAsDescribedAndNothingElseIsServed) {
  const cv::Mat floor = cv::imread(FLEETLOC_SOURCE_DIR "/deploy/demo/floors/rock_dirt_2048.png",
                                   cv::IMREAD_GRAYSCALE);
  testing::MapServerFixture server("supervisor_openapi", floor, kDomain, 0.0005, 256,
                                   R"("metrics": {"port": 0})");
  std::filesystem::create_directories(server.dir() / "sup");
  testing::SupervisorProcess supervisor(server.dir() / "sup", kDomain, kToken,
                                        {"--metrics-port", "0"});
  testing::FakeVehicle vehicle(server.participant(), "agv-1");
  const int port = supervisor.port();
  // The document served is the one in the source tree.
  std::ifstream in(FLEETLOC_SOURCE_DIR "/services/fleet_supervisor/openapi.json");
  const json source = json::parse(in);
  const Answer served = Raw(port, "GET", "/api/openapi.json", {}, "");
  ASSERT_EQ(served.status, 200);
  EXPECT_EQ(served.content_type, "application/json");
  doc_ = json::parse(served.body, nullptr, false);
  ASSERT_EQ(doc_, source);
  // Wait until the vehicle, the mosaic and the map server's re-mapping reader are known.
  ASSERT_TRUE(Eventually(
      [&] {
        vehicle.Publish(0.5);
        return Raw(port, "GET", "/api/vehicles/agv-1", {}, "").status == 200 &&
               Raw(port, "GET", "/api/mosaic", {}, "").status == 200 &&
               Raw(port, "GET", "/api/tiles/2/0/0.png", {}, "").status == 200;
      },
      20))
      << supervisor.log();

  const httplib::Headers token = {{"Authorization", std::string("Bearer ") + kToken}};
  int operations = 0;
  for (const auto& [path, item] : doc_["paths"].items()) {
    for (const auto& [method, operation] : item.items()) {
      std::string upper = method;
      for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
      const std::string target = Target(path, operation);
      std::string body;
      if (operation.contains("requestBody"))
        body = operation["requestBody"]["content"]["application/json"]["example"].dump();
      const Answer a = Raw(port, upper, target,
                           operation.contains("security") ? token : httplib::Headers{}, body);
      const std::string what = std::string(upper).append(" ").append(target);
      EXPECT_GE(a.status, 200) << what;
      EXPECT_LT(a.status, 300) << what << ": the documented example should succeed: "
                               << a.body.substr(0, 200);
      const std::string misfit = Described(operation, a, what);
      EXPECT_TRUE(misfit.empty()) << misfit;
      ++operations;
    }
  }
  EXPECT_EQ(operations, 16);  // with /healthz and /readyz (issue 22)

  // Documented failures answer as described.
  const std::tuple<std::string, std::string, std::string, httplib::Headers, std::string, int>
      failures[] = {
          {"/api/vehicles/{vehicle_id}", "GET", "/api/vehicles/bad*id", {}, "", 400},
          {"/api/vehicles/{vehicle_id}", "GET", "/api/vehicles/agv-zz", {}, "", 404},
          {"/api/vehicles/{vehicle_id}/history",
           "GET",
           "/api/vehicles/agv-1/history?max_points=1",
           {},
           "",
           400},
          {"/api/alerts", "GET", "/api/alerts?limit=0", {}, "", 400},
          {"/api/tiles/{level}/{col}/{row}.png", "GET", "/api/tiles/x/0/0.png", {}, "", 400},
          {"/api/tiles/{level}/{col}/{row}.png", "GET", "/api/tiles/0/99/99.png", {}, "", 404},
          {"/api/remap", "POST", "/api/remap", {}, R"({"region": [0, 0, 0.1, 0.1]})", 401},
          {"/api/remap",
           "POST",
           "/api/remap",
           {{"Authorization", "Bearer wrong-token-wrong"}},
           R"({"region": [0, 0, 0.1, 0.1]})",
           403},
          {"/api/remap", "POST", "/api/remap", token, R"({"region": [0, 0]})", 400},
          {"/api/auth", "GET", "/api/auth", {}, "", 401},
          {"/{file}", "GET", "/no-such-file.txt", {}, "", 404},
      };
  for (const auto& [path, method, target, headers, body, status] : failures) {
    std::string lower = method;
    for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    const Answer a = Raw(port, method, target, headers, body);
    EXPECT_EQ(a.status, status) << method << " " << target << ": " << a.body;
    const std::string misfit =
        Described(doc_["paths"][path][lower], a, std::string(method).append(" ").append(target));
    EXPECT_TRUE(misfit.empty()) << misfit;
  }

  // What the document does not list is not served: unknown paths, and documented paths with
  // methods the document does not give them.
  const std::pair<std::string, std::string> undocumented[] = {
      {"GET", "/api/unknown"},       {"GET", "/api/fleet/extra"},
      {"GET", "/api/vehicles"},      {"GET", "/api/vehicles/agv-1/history/x"},
      {"GET", "/api/tiles/0/0.png"}, {"GET", "/metrics"},
      {"GET", "/web/index.html"},    {"PUT", "/api/remap"},
      {"DELETE", "/api/remap"},      {"PATCH", "/api/fleet"}};
  for (const auto& [method, target] : undocumented) {
    const Answer a = Raw(port, method, target, token, method == "GET" ? "" : "{}");
    EXPECT_GE(a.status, 400) << method << " " << target << " is served but not documented";
    EXPECT_LT(a.status, 500) << method << " " << target;
  }
  for (const auto& [path, item] : doc_["paths"].items()) {
    if (item.contains("post")) continue;
    const Answer a = Raw(port, "POST", Target(path, item["get"]), token, "{}");
    EXPECT_GE(a.status, 400) << "POST " << path << " is served but not documented";
    EXPECT_LT(a.status, 500) << "POST " << path;
  }
}

}  // namespace
}  // namespace fleetloc
