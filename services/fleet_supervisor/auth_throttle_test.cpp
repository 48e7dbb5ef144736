// Wrong-token backoff: a few free tries, then waits doubling up to the cap, per client and
// overall; a right token clears the client.
#include "fleet_supervisor/auth_throttle.h"

#include <gtest/gtest.h>

namespace fleetloc::fleet_supervisor {
namespace {

// `prefix` followed by `i` (appended: GCC 12 warns falsely about "literal" + std::to_string).
std::string Client(std::string prefix, int i) {
  prefix += std::to_string(i);
  return prefix;
}

TEST(AuthThrottle, WaitsDoubleAfterTheFreeFailuresUpToTheCap) {
  AuthThrottle throttle({5, 1000, 1.0, 60.0, 16});
  double t = 100;
  for (int i = 0; i < 5; ++i) {
    EXPECT_EQ(throttle.RetryAfter("10.0.0.1", t), 0) << i;
    throttle.Failed("10.0.0.1", t);
  }
  EXPECT_DOUBLE_EQ(throttle.RetryAfter("10.0.0.1", t), 1.0);
  EXPECT_EQ(throttle.RetryAfter("10.0.0.2", t), 0);  // another client is not held up
  t += 1.0;
  throttle.Failed("10.0.0.1", t);  // the sixth: 2 s now
  EXPECT_DOUBLE_EQ(throttle.RetryAfter("10.0.0.1", t), 2.0);
  for (int i = 0; i < 20; ++i) throttle.Failed("10.0.0.1", t);
  EXPECT_DOUBLE_EQ(throttle.RetryAfter("10.0.0.1", t), 60.0);  // the cap
  EXPECT_DOUBLE_EQ(throttle.RetryAfter("10.0.0.1", t + 59.5), 0.5);
  throttle.Succeeded("10.0.0.1");
  EXPECT_EQ(throttle.RetryAfter("10.0.0.1", t), 0);
}

TEST(AuthThrottle, ManyClientsGuessingTogetherAreHeldUpTogether) {
  AuthThrottle throttle({5, 20, 1.0, 60.0, 4096});
  for (int i = 0; i < 20; ++i) throttle.Failed(Client("10.0.1.", i), 50.0);
  EXPECT_DOUBLE_EQ(throttle.RetryAfter("10.9.9.9", 50.0), 1.0);  // never guessed, still waits
  EXPECT_EQ(throttle.RetryAfter("10.9.9.9", 200.0), 0);
}

TEST(AuthThrottle, RemembersABoundedNumberOfClients) {
  AuthThrottle throttle({1, 100000, 1.0, 60.0, 3});
  for (int i = 0; i < 10; ++i) throttle.Failed(Client("c", i), i);
  EXPECT_EQ(throttle.RetryAfter("c0", 9.5), 0);  // forgotten (oldest)
  EXPECT_GT(throttle.RetryAfter("c9", 9.5), 0);
}

}  // namespace
}  // namespace fleetloc::fleet_supervisor
