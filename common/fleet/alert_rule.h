// A two-threshold alarm with hold times (hysteresis in value and in time): raised once a value
// has stayed above one threshold for a while, cleared once it has stayed below a lower one for a
// while, so a value hovering near a threshold does not make the alert flap.
#pragma once

#include <optional>

#include "base/status.h"

namespace fleetloc::fleet {

struct HysteresisOptions {
  double raise_above = 1.0;  // raised after the value is > raise_above for raise_after_s
  double clear_below = 0.5;  // cleared after the value is < clear_below for clear_after_s
  double raise_after_s = 0.0;
  double clear_after_s = 0.0;
};

// InvalidInput naming `name` unless clear_below <= raise_above and both hold times are >= 0.
Status Validate(const HysteresisOptions& options, const char* name);

class HysteresisAlarm {
 public:
  enum class Change { kNone, kRaised, kCleared };

  explicit HysteresisAlarm(const HysteresisOptions& options) : options_(options) {}

  // Feeds the value observed at time `t` (seconds; non-decreasing across calls) and says whether
  // the alarm was raised or cleared by it.
  Change Update(double t, double value);
  bool active() const { return active_; }
  // Sets the state without a hold (restoring an alert that was active before a restart).
  void Force(bool active) {
    active_ = active;
    pending_since_.reset();
  }

 private:
  HysteresisOptions options_;
  bool active_ = false;
  std::optional<double> pending_since_;  // when the value first crossed towards a change
};

}  // namespace fleetloc::fleet
