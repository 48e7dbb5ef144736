// Request head scanning and parsing.
#include "fleet_supervisor/request_head.h"

#include <algorithm>
#include <cctype>

namespace fleetloc::fleet_supervisor {
namespace {

std::string_view Trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r'))
    s.remove_suffix(1);
  return s;
}

bool IsToken(std::string_view s) {
  static constexpr std::string_view kSeparators = "()<>@,;:\\\"/[]?={} \t";
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) {
    const auto u = static_cast<unsigned char>(c);
    return u > 32 && u < 127 && kSeparators.find(c) == std::string_view::npos;
  });
}

std::string Lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

}  // namespace

HeadEnd FindHeadEnd(std::string_view received, const HeadLimits& limits) {
  int lines = 0;
  size_t line_start = 0;
  for (size_t i = 0; i < received.size() && i < limits.max_bytes; ++i) {
    if (received[i] != '\n') continue;
    const std::string_view line = received.substr(line_start, i - line_start);
    if (line.empty() || line == "\r") {
      // A blank line before the request line is tolerated (RFC 9112 §2.2); after it, the end.
      if (lines > 0) return {HeadState::kComplete, i + 1};
    } else if (++lines > limits.max_fields + 1) {
      return {HeadState::kTooManyFields, 0};
    }
    line_start = i + 1;
  }
  if (received.size() >= limits.max_bytes) return {HeadState::kTooLarge, 0};
  return {HeadState::kIncomplete, 0};
}

const std::string* RequestHead::Field(std::string_view lower_name) const {
  for (const auto& [name, value] : fields) {
    if (name == lower_name) return &value;
  }
  return nullptr;
}

int RequestHead::Count(std::string_view lower_name) const {
  return static_cast<int>(std::count_if(fields.begin(), fields.end(),
                                        [&](const auto& f) { return f.first == lower_name; }));
}

std::string_view RequestHead::Path() const {
  return std::string_view(target).substr(0, target.find('?'));
}

Result<RequestHead> ParseHead(std::string_view head) {
  RequestHead out;
  bool request_line = true;
  while (!head.empty()) {
    const size_t end = head.find('\n');
    std::string_view line = head.substr(0, end);
    head.remove_prefix(end == std::string_view::npos ? head.size() : end + 1);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (line.empty()) {
      if (request_line) continue;  // tolerated blank line before the request line
      break;
    }
    if (request_line) {
      const size_t a = line.find(' '), b = line.rfind(' ');
      if (a == std::string_view::npos || a == b) return InvalidInput("malformed request line");
      out.method = line.substr(0, a);
      out.target = line.substr(a + 1, b - a - 1);
      out.version = line.substr(b + 1);
      if (!IsToken(out.method) || out.target.empty()) return InvalidInput("malformed request line");
      if (out.version != "HTTP/1.1" && out.version != "HTTP/1.0") {
        return InvalidInput("unsupported HTTP version");
      }
      request_line = false;
      continue;
    }
    const size_t colon = line.find(':');
    if (colon == std::string_view::npos || !IsToken(line.substr(0, colon))) {
      return InvalidInput("malformed header field");
    }
    out.fields.emplace_back(Lower(line.substr(0, colon)),
                            std::string(Trim(line.substr(colon + 1))));
  }
  if (request_line) return InvalidInput("no request line");
  return out;
}

}  // namespace fleetloc::fleet_supervisor
