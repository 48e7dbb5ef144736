// FamilyBuilder and the text serialization.
#include "metrics/metric_families.h"

#include <prometheus/text_serializer.h>

#include <cstdio>
#include <cstdlib>
#include <limits>

namespace fleetloc::metrics {

std::string SanitizeName(const std::string& name) {
  std::string out;
  for (const char ch : name) {
    const bool ok = (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') ||
                    (ch >= '0' && ch <= '9') || ch == '_';
    out += ok ? ch : '_';
  }
  if (out.empty() || (out[0] >= '0' && out[0] <= '9')) out.insert(out.begin(), '_');
  return out;
}

FamilyBuilder::FamilyBuilder(std::string prefix, Labels const_labels)
    : prefix_(std::move(prefix)), const_labels_(std::move(const_labels)) {}

prometheus::ClientMetric& FamilyBuilder::Add(const std::string& name, const std::string& help,
                                             prometheus::MetricType type, const Labels& labels) {
  const std::string full = SanitizeName(prefix_ + name);
  prometheus::MetricFamily* family = nullptr;
  for (prometheus::MetricFamily& f : families_) family = f.name == full ? &f : family;
  if (!family) {
    families_.push_back({full, help, type, {}});
    family = &families_.back();
  } else if (family->type != type) {
    std::fprintf(stderr, "FamilyBuilder: metric %s used with two types\n", full.c_str());
    std::abort();
  }
  prometheus::ClientMetric& metric = family->metric.emplace_back();
  for (const Labels* set : std::initializer_list<const Labels*>{&const_labels_, &labels}) {
    for (const auto& [key, value] : *set) metric.label.push_back({SanitizeName(key), value});
  }
  return metric;
}

void FamilyBuilder::Counter(const std::string& name, const std::string& help, double value,
                            const Labels& labels) {
  Add(name + "_total", help, prometheus::MetricType::Counter, labels).counter.value = value;
}

void FamilyBuilder::Gauge(const std::string& name, const std::string& help, double value,
                          const Labels& labels) {
  Add(name, help, prometheus::MetricType::Gauge, labels).gauge.value = value;
}

void FamilyBuilder::Histogram(const std::string& name, const std::string& help,
                              const HistogramSnapshot& s, const Labels& labels) {
  prometheus::ClientMetric::Histogram& h =
      Add(name, help, prometheus::MetricType::Histogram, labels).histogram;
  h.sample_count = s.count;
  h.sample_sum = s.sum;
  for (size_t i = 0; i < s.cumulative.size(); ++i) {  // the last one is +Inf
    const double bound =
        i < s.upper_bounds.size() ? s.upper_bounds[i] : std::numeric_limits<double>::infinity();
    h.bucket.push_back({s.cumulative[i], bound});
  }
}

void FamilyBuilder::HealthCounters(
    const std::vector<std::pair<std::string, std::uint64_t>>& counters,
    const std::set<std::string>& gauges) {
  for (const auto& [name, value] : counters) {
    const std::string help = "ServiceHealth counter " + name;
    if (gauges.contains(name)) {
      Gauge(name, help, static_cast<double>(value));
    } else {
      Counter(name, help, static_cast<double>(value));
    }
  }
}

std::string ToText(const std::vector<prometheus::MetricFamily>& families) {
  return prometheus::TextSerializer().Serialize(families);
}

}  // namespace fleetloc::metrics
