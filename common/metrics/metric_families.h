// Builds Prometheus metric families from plain values (a service's health counters, gauges,
// histogram snapshots) and writes them in the text exposition format. Pure: no sockets, no
// threads; the services fill a builder each time they refresh their metrics.
#pragma once

#include <prometheus/metric_family.h>

#include <cstdint>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "metrics/histogram.h"

namespace fleetloc::metrics {

using Labels = std::vector<std::pair<std::string, std::string>>;

// `name` with every character outside [a-zA-Z0-9_] replaced by '_' (and a leading digit
// prefixed with '_'): a valid metric or label name.
std::string SanitizeName(const std::string& name);

class FamilyBuilder {
 public:
  // Every metric name gets `prefix` (e.g. "fleetloc_map_server_"); every series gets
  // `const_labels` (e.g. {{"service_id", "map-1"}}).
  FamilyBuilder(std::string prefix, Labels const_labels);

  // Adds one series to the family `name` (created with `help` on first use; a second use with
  // another type aborts: a programming error). Counters are named "<name>_total".
  void Counter(const std::string& name, const std::string& help, double value,
               const Labels& labels = {});
  void Gauge(const std::string& name, const std::string& help, double value,
             const Labels& labels = {});
  void Histogram(const std::string& name, const std::string& help,
                 const HistogramSnapshot& snapshot, const Labels& labels = {});
  // A service's health counters (ServiceHealth): each a counter "<counter>_total", except the
  // names in `gauges` (levels such as a queue depth), which are gauges.
  void HealthCounters(const std::vector<std::pair<std::string, std::uint64_t>>& counters,
                      const std::set<std::string>& gauges);

  std::vector<prometheus::MetricFamily> Take() { return std::move(families_); }

 private:
  prometheus::ClientMetric& Add(const std::string& name, const std::string& help,
                                prometheus::MetricType type, const Labels& labels);

  std::string prefix_;
  Labels const_labels_;
  std::vector<prometheus::MetricFamily> families_;
};

// The families in the text exposition format (version 0.0.4).
std::string ToText(const std::vector<prometheus::MetricFamily>& families);

}  // namespace fleetloc::metrics
