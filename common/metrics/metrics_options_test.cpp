// MetricsOptions from JSON: defaults, every key, unknown keys and bad values refused by name.
#include "metrics/metrics_options.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

namespace fleetloc::metrics {
namespace {

Status Read(const nlohmann::json& parent, MetricsOptions* o) {
  const io::JsonFields fields(parent, "svc.json");
  FLEETLOC_RETURN_IF_ERROR(ReadMetricsOptions(fields, parent, o));
  return Validate(*o, "svc.json");
}

TEST(MetricsOptions, DefaultsAreOffOnLoopback) {
  const MetricsOptions o;
  EXPECT_FALSE(o.enabled);
  EXPECT_EQ(o.bind, "127.0.0.1");
  EXPECT_TRUE(Validate(o, "x").ok());
}

TEST(MetricsOptions, ReadsEveryKey) {
  MetricsOptions o;
  const nlohmann::json parent = {{"metrics",
                                  {{"enabled", true},
                                   {"bind", "0.0.0.0"},
                                   {"port", 9464},
                                   {"port_file", "p"},
                                   {"threads", 2},
                                   {"request_timeout_s", 0.5},
                                   {"refresh_period_s", 2}}}};
  ASSERT_TRUE(Read(parent, &o).ok());
  EXPECT_TRUE(o.enabled);
  EXPECT_EQ(o.bind, "0.0.0.0");
  EXPECT_EQ(o.port, 9464);
  EXPECT_EQ(o.port_file, "p");
  EXPECT_EQ(o.threads, 2);
  EXPECT_EQ(o.request_timeout_s, 0.5);
  EXPECT_EQ(o.refresh_period_s, 2);
}

TEST(MetricsOptions, RefusesUnknownKeysAndBadValuesByName) {
  const std::pair<nlohmann::json, const char*> cases[] = {
      {{{"metrics", {{"enable", true}}}}, "field 'metrics.enable': unknown option"},
      {{{"metrics", {{"port", 70000}}}}, "metrics.port"},
      {{{"metrics", {{"port", 1.5}}}}, "metrics.port': must be an integer"},
      {{{"metrics", {{"threads", 0}}}}, "metrics.threads"},
      {{{"metrics", {{"threads", 9}}}}, "metrics.threads"},
      {{{"metrics", {{"enabled", "yes"}}}}, "metrics.enabled"},
      {{{"metrics", {{"request_timeout_s", 0}}}}, "metrics.request_timeout_s"},
      {{{"metrics", 3}}, "'metrics'"},
  };
  for (const auto& [parent, want] : cases) {
    MetricsOptions o;
    const Status s = Read(parent, &o);
    ASSERT_FALSE(s.ok()) << parent.dump();
    EXPECT_NE(s.message().find(want), std::string::npos) << s.message();
  }
}

}  // namespace
}  // namespace fleetloc::metrics
