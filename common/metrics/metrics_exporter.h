// Serves a service's metrics at http://<bind>:<port>/metrics (Prometheus text format) from a
// snapshot the service publishes: a scrape copies the last snapshot and never touches the
// service's state or waits for its loop, and the HTTP server (civetweb, inside prometheus-cpp)
// has a fixed number of threads and cuts off clients that do not send their request in time, so
// no client can stall the service.
#pragma once

#include <prometheus/metric_family.h>

#include <memory>
#include <string>
#include <vector>

#include "base/status.h"
#include "metrics/metrics_options.h"

namespace fleetloc::metrics {

class MetricsExporter {
 public:
  // Listens on options.bind:options.port (0: any free port) and writes the bound port to
  // options.port_file if set. Internal naming the address when it cannot listen.
  static Result<std::unique_ptr<MetricsExporter>> Start(const MetricsOptions& options);
  ~MetricsExporter();

  // Replaces what the next scrapes return. Thread-safe; O(1) under the lock.
  void Publish(std::vector<prometheus::MetricFamily> families);
  int port() const { return port_; }

 private:
  class Snapshot;
  struct Server;
  MetricsExporter() = default;

  std::shared_ptr<Snapshot> snapshot_;
  std::unique_ptr<Server> server_;
  int port_ = 0;
};

// A service's /metrics as configured: off, serving, or failed to start — then logged once, and
// `error()` is what the service reports as its health issue "metrics_unavailable"; the service
// runs on without metrics. Used from the service's own loop thread.
class ServiceMetrics {
 public:
  // Starts the exporter when options.enabled; `service` names it in the log.
  ServiceMetrics(const MetricsOptions& options, const std::string& service);

  bool serving() const { return exporter_ != nullptr; }
  // True at most once per refresh period while serving (the caller then builds and publishes).
  bool Due();
  void Publish(std::vector<prometheus::MetricFamily> families);
  int port() const { return exporter_ ? exporter_->port() : 0; }
  const std::string& error() const { return error_; }

 private:
  MetricsOptions options_;
  std::unique_ptr<MetricsExporter> exporter_;
  std::string error_;
  double next_refresh_ = 0;  // steady clock seconds
};

}  // namespace fleetloc::metrics
