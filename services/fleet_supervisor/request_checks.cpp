// Request head checks of the connection front.
#include "fleet_supervisor/request_checks.h"

#include <algorithm>
#include <cctype>
#include <charconv>

namespace fleetloc::fleet_supervisor {
namespace {

std::string Lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

// "[::1]:8080" → "::1", "Example.org:80" → "example.org", "example.org" → "example.org".
std::string HostPart(std::string_view field) {
  if (!field.empty() && field.front() == '[') {
    const size_t close = field.find(']');
    return close == std::string_view::npos ? "" : Lower(field.substr(1, close - 1));
  }
  const size_t colon = field.find(':');
  return Lower(field.substr(0, colon));
}

std::string WithoutBrackets(std::string_view host) {
  if (host.size() >= 2 && host.front() == '[' && host.back() == ']')
    host = host.substr(1, host.size() - 2);
  return Lower(host);
}

std::optional<Refusal> TargetProblem(std::string_view target) {
  if (target.empty() || (target.front() != '/' && target != "*")) {
    return Refusal{400, "the request target must be a path"};
  }
  for (size_t i = 0; i < target.size(); ++i) {
    const auto c = static_cast<unsigned char>(target[i]);
    if (c < 0x20 || c == 0x7f) return Refusal{400, "control byte in the request target"};
    if (c == '%' && i + 2 < target.size() && target[i + 1] == '0' && target[i + 2] == '0') {
      return Refusal{400, "NUL (%00) in the request target"};
    }
  }
  return std::nullopt;
}

}  // namespace

std::vector<std::string> DefaultAllowedHosts(const std::string& bind) {
  std::vector<std::string> hosts = {"localhost", "127.0.0.1", "::1"};
  const std::string b = WithoutBrackets(bind);
  if (!b.empty() && b != "0.0.0.0" && b != "::" &&
      std::find(hosts.begin(), hosts.end(), b) == hosts.end()) {
    hosts.push_back(b);
  }
  return hosts;
}

bool HostAllowed(std::string_view host_field, const std::vector<std::string>& allowed) {
  const std::string host = HostPart(host_field);
  if (host.empty()) return false;
  for (const std::string& a : allowed) {
    if (a == "*" || WithoutBrackets(a) == host) return true;
  }
  return false;
}

int RangeCount(std::string_view field) {
  const size_t eq = field.find('=');
  if (eq == std::string_view::npos || Lower(field.substr(0, eq)) != "bytes") return -1;
  std::string_view specs = field.substr(eq + 1);
  int count = 0;
  while (true) {
    const size_t comma = specs.find(',');
    std::string_view spec = specs.substr(0, comma);
    while (!spec.empty() && spec.front() == ' ') spec.remove_prefix(1);
    while (!spec.empty() && spec.back() == ' ') spec.remove_suffix(1);
    if (spec.empty() || spec.find('-') == std::string_view::npos) return -1;
    ++count;
    if (comma == std::string_view::npos) return count;
    specs.remove_prefix(comma + 1);
  }
}

std::optional<Refusal> BodyProblem(const RequestHead& head, const RequestPolicy& policy,
                                   size_t* body_bytes) {
  *body_bytes = 0;
  if (head.Field("transfer-encoding") != nullptr) {
    return Refusal{411, "request bodies must carry a Content-Length (no Transfer-Encoding)"};
  }
  const std::string* length = nullptr;
  for (const auto& [name, value] : head.fields) {
    if (name != "content-length") continue;
    if (length != nullptr && *length != value)
      return Refusal{400, "conflicting Content-Length fields"};
    length = &value;
  }
  if (length == nullptr) return std::nullopt;
  unsigned long long n = 0;
  const char* end = length->data() + length->size();
  auto [ptr, ec] = std::from_chars(length->data(), end, n);
  if (ec != std::errc() || ptr != end || length->empty())
    return Refusal{400, "malformed Content-Length"};
  if (n > policy.max_body_bytes) {
    return Refusal{413, "request body of " + std::to_string(n) + " bytes, more than " +
                            std::to_string(policy.max_body_bytes)};
  }
  *body_bytes = static_cast<size_t>(n);
  return std::nullopt;
}

std::optional<Refusal> CheckRequest(const RequestHead& head, const RequestPolicy& policy,
                                    size_t* body_bytes) {
  *body_bytes = 0;
  if (auto problem = TargetProblem(head.target)) return problem;
  if (head.Count("host") > 1) return Refusal{400, "more than one Host field"};
  const std::string* host = head.Field("host");
  if (host == nullptr) return Refusal{400, "a Host field is required"};
  if (!HostAllowed(*host, policy.allowed_hosts)) {
    return Refusal{421, "host '" + HostPart(*host).substr(0, 64) +
                            "' is not served here (see the supervisor's http.allowed_hosts)"};
  }
  if (const std::string* range = head.Field("range")) {
    const int ranges = RangeCount(*range);
    if (ranges < 0 || ranges > policy.max_ranges || head.Count("range") > 1) {
      return Refusal{416,
                     "at most " + std::to_string(policy.max_ranges) + " byte range(s) per request"};
    }
  }
  if (const std::string* expect = head.Field("expect");
      expect != nullptr && Lower(*expect) != "100-continue") {
    return Refusal{417, "unsupported Expect"};
  }
  return BodyProblem(head, policy, body_bytes);
}

}  // namespace fleetloc::fleet_supervisor
