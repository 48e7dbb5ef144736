// What the supervisor's connection front refuses before a request reaches a handler: a Host that
// is not one of this supervisor's names (DNS rebinding: a page of another site reading the API
// through an operator's browser), a target with a NUL (%00) or control byte, more byte ranges than
// allowed (amplification), a body that is too large or not length-delimited, an unknown Expect.
// Pure: the head in, a refusal (status and message) or nothing out.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "fleet_supervisor/request_head.h"

namespace fleetloc::fleet_supervisor {

struct RequestPolicy {
  std::vector<std::string> allowed_hosts;  // lower-case host names / addresses, no port; "*": any
  int max_ranges = 1;
  size_t max_body_bytes = 64 * 1024;
};

struct Refusal {
  int status = 400;
  std::string message;
};

// The Host names a supervisor bound to `bind` answers to by default: localhost, 127.0.0.1, ::1,
// and `bind` itself unless it is a wildcard address (0.0.0.0, ::).
std::vector<std::string> DefaultAllowedHosts(const std::string& bind);

// True when the Host field's host part (port removed; IPv6 in brackets) is in `allowed`.
bool HostAllowed(std::string_view host_field, const std::vector<std::string>& allowed);

// The number of byte ranges in a Range field ("bytes=0-9,20-29" → 2); -1 when malformed.
int RangeCount(std::string_view range_field);

// The body length the head announces (0 without Content-Length); a refusal when it cannot be
// accepted (chunked or unparsable lengths, more than max_body_bytes).
std::optional<Refusal> BodyProblem(const RequestHead& head, const RequestPolicy& policy,
                                   size_t* body_bytes);

// Every check on a parsed head (Host, target, ranges, Expect, body). Nothing when it may go on.
std::optional<Refusal> CheckRequest(const RequestHead& head, const RequestPolicy& policy,
                                    size_t* body_bytes);

}  // namespace fleetloc::fleet_supervisor
