// For tests that wait on another process or thread: polls a condition until it holds or a time
// limit passes. Shared by the transport unit tests and the integration tests in tests/.
#pragma once

#include <chrono>
#include <functional>
#include <thread>

namespace fleetloc::testing {

// Polls `done` every 10 ms for up to `limit_s`; true once it holds.
inline bool Eventually(const std::function<bool()>& done, double limit_s = 20.0) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(limit_s);
  while (std::chrono::steady_clock::now() < end) {
    if (done()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return done();
}

}  // namespace fleetloc::testing
