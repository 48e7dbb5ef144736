// ServiceHealth filling and writing (see service_health_messages.h).
#include "transport/service_health_messages.h"

#include <algorithm>

#include "transport/wire_util.h"

namespace fleetloc::transport {

Status WriteServiceHealth(const Writer<fleetloc_ServiceHealth>& writer,
                          const ServiceHealthReport& report) {
  fleetloc_ServiceHealth health{};
  health.wire_version = fleetloc_CURRENT_WIRE_VERSION;
  SetBounded(health.service_id, report.service_id);
  SetBounded(health.kind, report.kind);
  health.stamp = NowStamp();
  std::vector<fleetloc_Counter> counters;
  for (const auto& [name, value] : report.counters) {
    if (counters.size() == 64) break;  // the IDL bound
    fleetloc_Counter counter{};
    SetBounded(counter.name, name);
    counter.value = value;
    counters.push_back(counter);
  }
  health.counters._buffer = counters.data();
  health.counters._length = health.counters._maximum = static_cast<uint32_t>(counters.size());
  fleetloc_HealthIssue issue{};
  health.level = fleetloc_HEALTH_OK;
  if (report.issue) {
    health.level = report.issue->level;
    SetBounded(issue.name, report.issue->name);
    issue.level = report.issue->level;
    SetBounded(issue.message, report.issue->message);
    health.issues._buffer = &issue;
    health.issues._length = health.issues._maximum = 1;
  }
  return writer.Write(health);
}

}  // namespace fleetloc::transport
