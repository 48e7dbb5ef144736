// MetricsOptions from JSON.
#include "metrics/metrics_options.h"

#include <nlohmann/json.hpp>

namespace fleetloc::metrics {

Status Validate(const MetricsOptions& o, const std::string& service) {
  auto bad = [&](const std::string& field, const std::string& what) {
    return InvalidInput(service + ": field 'metrics." + field + "': " + what);
  };
  if (o.bind.empty()) return bad("bind", "is empty");
  if (o.port < 0 || o.port > 65535) return bad("port", "must be in [0, 65535]");
  if (o.threads < 1 || o.threads > 4) return bad("threads", "must be in [1, 4]");
  if (!(o.request_timeout_s >= 0.1 && o.request_timeout_s <= 60))
    return bad("request_timeout_s", "must be in [0.1, 60]");
  if (!(o.refresh_period_s >= 0.1 && o.refresh_period_s <= 60))
    return bad("refresh_period_s", "must be in [0.1, 60]");
  return Status::Ok();
}

Status ReadMetricsOptions(const io::JsonFields& fields, const nlohmann::json& parent,
                          MetricsOptions* o) {
  Result<io::JsonFields> metrics = fields.Object("metrics");
  if (!metrics.ok()) return metrics.status();
  for (const auto& [key, value] : parent.at("metrics").items()) {
    bool known = false;
    for (const char* name : {"enabled", "bind", "port", "port_file", "threads", "request_timeout_s",
                             "refresh_period_s"}) {
      known |= key == name;
    }
    if (!known) return metrics->Error(key, "unknown option");
  }
  if (metrics->Has("enabled")) FLEETLOC_RETURN_IF_ERROR(metrics->Bool("enabled", &o->enabled));
  if (metrics->Has("bind")) FLEETLOC_RETURN_IF_ERROR(metrics->NonEmptyString("bind", &o->bind));
  if (metrics->Has("port_file"))
    FLEETLOC_RETURN_IF_ERROR(metrics->NonEmptyString("port_file", &o->port_file));
  for (const auto& [name, out] : {std::pair{"port", &o->port}, {"threads", &o->threads}}) {
    if (!metrics->Has(name)) continue;
    double value = 0;
    FLEETLOC_RETURN_IF_ERROR(metrics->NonNegativeNumber(name, &value));
    if (value != static_cast<int>(value)) return metrics->Error(name, "must be an integer");
    *out = static_cast<int>(value);
  }
  for (const auto& [name, out] : {std::pair{"request_timeout_s", &o->request_timeout_s},
                                  {"refresh_period_s", &o->refresh_period_s}}) {
    if (metrics->Has(name)) FLEETLOC_RETURN_IF_ERROR(metrics->PositiveNumber(name, out));
  }
  return Status::Ok();
}

}  // namespace fleetloc::metrics
