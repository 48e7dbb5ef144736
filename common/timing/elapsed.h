// Elapsed wall time in milliseconds since a steady-clock instant, for the step timings a cycle
// reports. Header only.
#pragma once

#include <chrono>

namespace fleetloc::timing {

inline double MsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

}  // namespace fleetloc::timing
