// Wire helpers: entity id check, stamps, borrowed octet sequences.
#include "transport/wire_util.h"

#include <cmath>

namespace fleetloc::transport {

bool IsValidEntityId(std::string_view id) {
  if (id.empty() || id.size() > 11) return false;
  for (const char c : id) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                    c == '_' || c == '-';
    if (!ok) return false;
  }
  return true;
}

fleetloc_TimeStamp ToStamp(double seconds) {
  fleetloc_TimeStamp stamp{};
  const double whole = std::floor(seconds);
  stamp.sec = static_cast<int64_t>(whole);
  stamp.nanosec = static_cast<uint32_t>(std::min(999999999.0, std::round((seconds - whole) * 1e9)));
  return stamp;
}

fleetloc_TimeStamp NowStamp() {
  const auto now = std::chrono::system_clock::now().time_since_epoch();
  return ToStamp(std::chrono::duration<double>(now).count());
}

double ToSeconds(const fleetloc_TimeStamp& stamp) {
  return static_cast<double>(stamp.sec) + stamp.nanosec * 1e-9;
}

dds_sequence_octet BorrowOctets(std::span<const std::uint8_t> bytes) {
  dds_sequence_octet seq{};
  seq._buffer = const_cast<std::uint8_t*>(bytes.data());  // DDS only reads it while writing
  seq._length = seq._maximum = static_cast<uint32_t>(bytes.size());
  seq._release = false;
  return seq;
}

}  // namespace fleetloc::transport
