// MetricsExporter: prometheus-cpp's Exposer over a snapshot Collectable.
#include "metrics/metrics_exporter.h"

#include <prometheus/collectable.h>
#include <prometheus/exposer.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <exception>
#include <fstream>
#include <mutex>

namespace fleetloc::metrics {

// The last published families; a scrape copies them.
class MetricsExporter::Snapshot : public prometheus::Collectable {
 public:
  void Set(std::vector<prometheus::MetricFamily> families) {
    auto next = std::make_shared<const std::vector<prometheus::MetricFamily>>(std::move(families));
    std::lock_guard<std::mutex> lock(mutex_);
    families_.swap(next);
  }
  std::vector<prometheus::MetricFamily> Collect() const override {
    std::shared_ptr<const std::vector<prometheus::MetricFamily>> current;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      current = families_;
    }
    return current ? *current : std::vector<prometheus::MetricFamily>();
  }

 private:
  mutable std::mutex mutex_;
  std::shared_ptr<const std::vector<prometheus::MetricFamily>> families_;
};

struct MetricsExporter::Server {
  std::unique_ptr<prometheus::Exposer> exposer;
};

Result<std::unique_ptr<MetricsExporter>> MetricsExporter::Start(const MetricsOptions& options) {
  FLEETLOC_RETURN_IF_ERROR(Validate(options, "metrics"));
  const bool v6 = options.bind.find(':') != std::string::npos;
  const std::string address =
      (v6 ? "[" + options.bind + "]" : options.bind) + ":" + std::to_string(options.port);
  std::unique_ptr<MetricsExporter> exporter(new MetricsExporter());
  exporter->snapshot_ = std::make_shared<Snapshot>();
  exporter->server_ = std::make_unique<Server>();
  try {
    exporter->server_->exposer = std::make_unique<prometheus::Exposer>(std::vector<std::string>{
        "listening_ports", address, "num_threads", std::to_string(options.threads),
        "request_timeout_ms", std::to_string(static_cast<int>(options.request_timeout_s * 1000)),
        "enable_keep_alive", "no"});
    exporter->server_->exposer->RegisterCollectable(exporter->snapshot_);
    const std::vector<int> ports = exporter->server_->exposer->GetListeningPorts();
    if (ports.empty()) return Internal("metrics: cannot listen on " + address);
    exporter->port_ = ports.front();
  } catch (const std::exception& e) {
    return Internal("metrics: cannot listen on " + address + ": " + e.what());
  }
  if (!options.port_file.empty()) {
    std::ofstream out(options.port_file);
    out << exporter->port_ << "\n";
    if (!out) return Internal(options.port_file + ": cannot write the metrics port");
  }
  return exporter;
}

MetricsExporter::~MetricsExporter() = default;

void MetricsExporter::Publish(std::vector<prometheus::MetricFamily> families) {
  snapshot_->Set(std::move(families));
}

ServiceMetrics::ServiceMetrics(const MetricsOptions& options, const std::string& service)
    : options_(options) {
  if (!options.enabled) return;
  Result<std::unique_ptr<MetricsExporter>> started = MetricsExporter::Start(options);
  if (!started.ok()) {
    error_ = started.status().message();
    spdlog::error("{}: {}; running without /metrics", service, error_);
    return;
  }
  exporter_ = std::move(started).value();
  spdlog::info("{}: metrics at http://{}:{}/metrics", service, options.bind, exporter_->port());
}

bool ServiceMetrics::Due() {
  if (!exporter_) return false;
  const double now =
      std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
  if (now < next_refresh_) return false;
  next_refresh_ = now + options_.refresh_period_s;
  return true;
}

void ServiceMetrics::Publish(std::vector<prometheus::MetricFamily> families) {
  if (exporter_) exporter_->Publish(std::move(families));
}

}  // namespace fleetloc::metrics
