// CaptureLatency: totals and stages from known times, the warm-up poses apart, a source that
// cannot time its arrival, and the bound on what is kept.
#include "tracker_agent/capture_latency.h"

#include <gtest/gtest.h>

namespace fleetloc::tracker_agent {
namespace {

TEST(CaptureLatency, StagesSplitTheTotalAtEachMark) {
  CaptureLatency latency;
  // Captured at 100 s; arrived 1 ms later; taken 0.5 ms after; cycle from 102 ms; out at 105 ms.
  latency.Record({100.0, 100.001, 100.0015}, 100.002, 100.005);
  const nlohmann::json s = latency.Summary();
  EXPECT_NEAR(s["p50"].get<double>(), 5.0, 1e-6);
  EXPECT_NEAR(s["stages"]["camera"]["p50"].get<double>(), 1.0, 1e-6);
  EXPECT_NEAR(s["stages"]["input"]["p50"].get<double>(), 0.5, 1e-6);
  EXPECT_NEAR(s["stages"]["before_cycle"]["p50"].get<double>(), 0.5, 1e-6);
  EXPECT_NEAR(s["stages"]["cycle_and_publish"]["p50"].get<double>(), 3.0, 1e-6);
}

TEST(CaptureLatency, AnArrivalTheSourceCannotTellCountsInTheInputStage) {
  CaptureLatency latency;
  latency.Record({10.0, 0.0, 10.004}, 10.004, 10.006);
  const nlohmann::json s = latency.Summary();
  EXPECT_NEAR(s["stages"]["camera"]["p50"].get<double>(), 0.0, 1e-9);
  EXPECT_NEAR(s["stages"]["input"]["p50"].get<double>(), 4.0, 1e-6);
  EXPECT_NEAR(s["p50"].get<double>(), 6.0, 1e-6);
}

TEST(CaptureLatency, TheFirstPosesAreReportedApartFromTheSteadyOnes) {
  CaptureLatency latency;
  for (int i = 0; i < CaptureLatency::kWarmupPoses; ++i) latency.Record({1.0, 1.0, 1.0}, 1.0, 1.05);
  for (int i = 0; i < 100; ++i) latency.Record({2.0, 2.0, 2.0}, 2.0, 2.003);
  const nlohmann::json s = latency.Summary();
  EXPECT_EQ(s["frames"].get<size_t>(), 120u);
  EXPECT_EQ(s["steady"]["frames"].get<size_t>(), 100u);
  EXPECT_NEAR(s["steady"]["p99"].get<double>(), 3.0, 1e-6);
  ASSERT_EQ(s["first_ms"].size(), static_cast<size_t>(CaptureLatency::kWarmupPoses));
  EXPECT_NEAR(s["first_ms"][0].get<double>(), 50.0, 1e-6);
  EXPECT_GT(s["p99"].get<double>(), 40.0);  // the all-poses figure keeps them
}

TEST(CaptureLatency, KeepsTheLastPosesOnly) {
  CaptureLatency latency;
  const size_t n = CaptureLatency::kKept + 500;
  for (size_t i = 0; i < n; ++i) latency.Record({0.0, 0.0, 0.0}, 0.0, i < 500 ? 1.0 : 0.002);
  const nlohmann::json s = latency.Summary();
  EXPECT_EQ(s["frames"].get<size_t>(), CaptureLatency::kKept);
  EXPECT_NEAR(s["p99"].get<double>(), 2.0, 1e-6);  // the slow first 500 are gone
  EXPECT_TRUE(s["first_ms"].empty());              // and with them the warm-up ones
  EXPECT_EQ(s["stages"]["cycle_and_publish"]["frames"].get<size_t>(), CaptureLatency::kKept);
}

}  // namespace
}  // namespace fleetloc::tracker_agent
