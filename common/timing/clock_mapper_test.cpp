// ClockMapper: a device clock with an unknown offset and random transport delays is mapped to the
// capture times on the host clock to the smallest delay seen; a restarted device clock recovers.
#include "timing/clock_mapper.h"

#include <gtest/gtest.h>

#include <random>

namespace fleetloc::timing {
namespace {

TEST(ClockMapper, RecoversCaptureTimesToTheSmallestDelay) {
  std::mt19937 rng(3);
  std::exponential_distribution<double> extra_delay(1.0 / 0.004);  // 4 ms mean on top of 0.5 ms
  const double device_to_host = 1.7e9 - 12.345;  // a camera counting from its power-up
  ClockMapper mapper;
  double worst_after_warmup = 0;
  for (int i = 0; i < 300; ++i) {
    const double capture_host = 1.7e9 + i * 0.04;
    const double arrival = capture_host + 0.0005 + extra_delay(rng);
    const double mapped = mapper.Map(capture_host - device_to_host, arrival);
    EXPECT_LE(mapped, arrival);
    if (i >= 50) worst_after_warmup = std::max(worst_after_warmup, std::abs(mapped - capture_host));
  }
  // Only the constant 0.5 ms and the smallest extra delay of the window remain.
  EXPECT_LT(worst_after_warmup, 0.0006);
  EXPECT_GT(worst_after_warmup, 0.0004);
  EXPECT_EQ(mapper.resets(), 0);
}

TEST(ClockMapper, ADeviceClockRestartStartsANewWindow) {
  ClockMapper mapper;
  for (int i = 0; i < 20; ++i) mapper.Map(100.0 + i * 0.1, 5000.0 + i * 0.1 + 0.001);
  EXPECT_NEAR(*mapper.offset(), 4900.001, 1e-9);
  EXPECT_EQ(mapper.samples(), 20);
  // The camera rebooted: its counter starts again near zero.
  const double mapped = mapper.Map(0.2, 5010.0 + 0.002);
  EXPECT_NEAR(mapped, 5010.002, 1e-9);
  EXPECT_EQ(mapper.resets(), 1);
  EXPECT_EQ(mapper.samples(), 1);  // a new mapping: its first captures are not yet to be trusted
  EXPECT_NEAR(mapper.Map(0.3, 5010.1 + 0.001), 5010.101, 1e-9);
  EXPECT_EQ(mapper.samples(), 2);
}

TEST(ClockMapper, TheOffsetFollowsADriftingClockThroughTheWindow) {
  ClockMapper mapper({2.0, 1.0});
  double mapped = 0;
  for (int i = 0; i < 1000; ++i) {
    const double host = 1000.0 + i * 0.05;
    const double device = host * (1 - 100e-6);  // 100 ppm slow: the offset grows
    mapped = mapper.Map(device, host + 0.001);
  }
  // The minimum is the offset of 2 s ago: 100 ppm of 2 s = 0.2 ms behind, not more.
  EXPECT_NEAR(mapped, 1000.0 + 999 * 0.05 + 0.001 - 0.0002, 0.00001);
}

}  // namespace
}  // namespace fleetloc::timing
