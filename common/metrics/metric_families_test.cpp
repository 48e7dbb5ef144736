// FamilyBuilder and ToText: names, labels, counters vs gauges, histograms — read back with the
// strict exposition parser.
#include "metrics/metric_families.h"

#include <gtest/gtest.h>

#include "metrics/exposition.h"

namespace fleetloc::metrics {
namespace {

TEST(SanitizeName, ReplacesCharactersOutsideTheNameAlphabet) {
  EXPECT_EQ(SanitizeName("tiles-served.total"), "tiles_served_total");
  EXPECT_EQ(SanitizeName("9lives"), "_9lives");
  EXPECT_EQ(SanitizeName(""), "_");
}

TEST(FamilyBuilder, HealthCountersBecomeCountersExceptTheNamedGauges) {
  FamilyBuilder b("fleetloc_test_", {{"service_id", "map-1"}});
  b.HealthCounters({{"tiles_served", 42}, {"history_queue", 7}}, {"history_queue"});
  const std::string text = ToText(b.Take());
  Result<Exposition> e = ParseExposition(text);
  ASSERT_TRUE(e.ok()) << e.status().message() << "\n" << text;
  EXPECT_EQ(e->types.at("fleetloc_test_tiles_served_total"), "counter");
  EXPECT_EQ(e->types.at("fleetloc_test_history_queue"), "gauge");
  EXPECT_EQ(*e->Value("fleetloc_test_tiles_served_total", {{"service_id", "map-1"}}), 42);
  EXPECT_EQ(*e->Value("fleetloc_test_history_queue"), 7);
}

TEST(FamilyBuilder, SeriesOfOneNameShareAFamily) {
  FamilyBuilder b("p_", {});
  b.Gauge("vehicles", "by lock state", 3, {{"lock_state", "tracking"}});
  b.Gauge("vehicles", "by lock state", 1, {{"lock_state", "lost"}});
  const std::vector<prometheus::MetricFamily> families = b.Take();
  ASSERT_EQ(families.size(), 1u);
  EXPECT_EQ(families[0].metric.size(), 2u);
  Result<Exposition> e = ParseExposition(ToText(families));
  ASSERT_TRUE(e.ok()) << e.status().message();
  EXPECT_EQ(*e->Value("p_vehicles", {{"lock_state", "lost"}}), 1);
}

TEST(FamilyBuilder, HistogramHasCumulativeBucketsAndInf) {
  Histogram h({0.001, 0.01});
  h.Observe(0.0005);
  h.Observe(0.005);
  h.Observe(5);
  FamilyBuilder b("p_", {});
  b.Histogram("cycle_seconds", "tracker cycle", h.Snapshot());
  const std::string text = ToText(b.Take());
  Result<Exposition> e = ParseExposition(text);
  ASSERT_TRUE(e.ok()) << e.status().message() << "\n" << text;
  EXPECT_EQ(*e->Value("p_cycle_seconds_bucket", {{"le", "0.001"}}), 1);
  EXPECT_EQ(*e->Value("p_cycle_seconds_bucket", {{"le", "0.01"}}), 2);
  EXPECT_EQ(*e->Value("p_cycle_seconds_bucket", {{"le", "+Inf"}}), 3);
  EXPECT_EQ(*e->Value("p_cycle_seconds_count"), 3);
  EXPECT_NEAR(*e->Value("p_cycle_seconds_sum"), 5.0055, 1e-9);
}

TEST(FamilyBuilder, LabelValuesAreEscaped) {
  FamilyBuilder b("p_", {});
  b.Gauge("g", "help", 1, {{"vehicle", "a\"b\\c\nd"}});
  Result<Exposition> e = ParseExposition(ToText(b.Take()));
  ASSERT_TRUE(e.ok()) << e.status().message();
  EXPECT_EQ(e->samples.at(0).labels.at("vehicle"), "a\"b\\c\nd");
}

TEST(FamilyBuilderDeathTest, OneNameWithTwoTypesIsAProgrammingError) {
  FamilyBuilder b("p_", {});
  b.Gauge("x_total", "h", 1);
  EXPECT_DEATH(b.Counter("x", "h", 1), "two types");
}

}  // namespace
}  // namespace fleetloc::metrics
