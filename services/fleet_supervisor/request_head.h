// The head of an HTTP/1.x request as the supervisor's connection front reads it off a socket,
// before any worker thread sees it: where the head ends (within a byte and a field-count limit),
// and its request line and fields. Pure: bytes in, values out.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "base/status.h"

namespace fleetloc::fleet_supervisor {

struct HeadLimits {
  size_t max_bytes = 16384;  // request line, fields and the blank line
  int max_fields = 64;       // header fields (lines after the request line)
};

enum class HeadState {
  kIncomplete,     // no blank line yet, within the limits: read more
  kComplete,       // `length` bytes are the head
  kTooLarge,       // more than max_bytes without the blank line
  kTooManyFields,  // more than max_fields lines before it
};

struct HeadEnd {
  HeadState state = HeadState::kIncomplete;
  size_t length = 0;  // when complete: bytes of the head, blank line included
};

// Looks for the end of the head in the bytes received so far (CRLF or bare LF line ends).
HeadEnd FindHeadEnd(std::string_view received, const HeadLimits& limits);

struct RequestHead {
  std::string method;
  std::string target;                                       // as sent (not decoded)
  std::string version;                                      // "HTTP/1.1"
  std::vector<std::pair<std::string, std::string>> fields;  // names lower-cased, values trimmed

  // The first value of field `lower_name`, or nullptr.
  const std::string* Field(std::string_view lower_name) const;
  int Count(std::string_view lower_name) const;
  // The target's path (before '?').
  std::string_view Path() const;
};

// Parses a complete head (FindHeadEnd said kComplete; `head` is its `length` bytes).
// InvalidInput with a short reason for a malformed request line or field.
Result<RequestHead> ParseHead(std::string_view head);

}  // namespace fleetloc::fleet_supervisor
