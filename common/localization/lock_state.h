// The vocabulary of a localization result that every layer speaks: a frame's lock state. The
// tracker produces it, the agent publishes it, the fleet logic counts it and the wire carries it;
// a header of its own keeps the fleet logic and the wire conversions off the tracker's library.
#pragma once

namespace fleetloc::localization {

enum class LockState { kTracking, kCoasting, kLost, kRelocalized };

// "tracking", "coasting", "lost", "relocalized".
constexpr const char* LockStateName(LockState state) {
  switch (state) {
    case LockState::kTracking:
      return "tracking";
    case LockState::kCoasting:
      return "coasting";
    case LockState::kLost:
      return "lost";
    case LockState::kRelocalized:
      return "relocalized";
  }
  return "lost";
}

}  // namespace fleetloc::localization
