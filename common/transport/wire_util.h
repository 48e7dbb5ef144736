// Small helpers for filling and checking generated wire structs: bounded strings, stamps,
// entity ids, octet sequences that borrow a caller's buffer.
#pragma once

#include <chrono>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "transport/fleetloc_types.h"

namespace fleetloc::transport {

// Copies `text` into a bounded IDL string (char[N]); false (and a truncated copy) if it is longer.
template <size_t N>
bool SetBounded(char (&dst)[N], std::string_view text) {
  const size_t n = std::min(text.size(), N - 1);
  text.copy(dst, n);
  dst[n] = '\0';
  return n == text.size();
}

// The string in a received bounded IDL string; stops at the array end even without a NUL.
template <size_t N>
std::string GetBounded(const char (&src)[N]) {
  size_t n = 0;
  while (n < N && src[n] != '\0') ++n;
  return std::string(src, n);
}

// Vehicle, server and service ids: 1–11 characters of [A-Za-z0-9_-] (they name DDS partitions,
// where '*' and '?' would be wildcards, and keys bounded for other vendors: docs/topics.md,
// "Interoperability with a second vendor").
bool IsValidEntityId(std::string_view id);

fleetloc_TimeStamp NowStamp();
fleetloc_TimeStamp ToStamp(double seconds);
double ToSeconds(const fleetloc_TimeStamp& stamp);

// An octet sequence pointing at `bytes` (not owned, not released by DDS) for writing.
dds_sequence_octet BorrowOctets(std::span<const std::uint8_t> bytes);
inline std::span<const std::uint8_t> OctetSpan(const dds_sequence_octet& seq) {
  return {seq._buffer, seq._length};
}

}  // namespace fleetloc::transport
