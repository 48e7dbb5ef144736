// HysteresisAlarm: value and time hysteresis.
#include "fleet/alert_rule.h"

#include <string>

namespace fleetloc::fleet {

Status Validate(const HysteresisOptions& o, const char* name) {
  const std::string field = name;
  if (!(o.clear_below <= o.raise_above)) {
    return InvalidInput("alert '" + field + "': clear_below must be <= raise_above");
  }
  if (!(o.raise_after_s >= 0 && o.clear_after_s >= 0)) {
    return InvalidInput("alert '" + field + "': hold times must be >= 0");
  }
  return Status::Ok();
}

HysteresisAlarm::Change HysteresisAlarm::Update(double t, double value) {
  const bool crossing = active_ ? value < options_.clear_below : value > options_.raise_above;
  if (!crossing) {
    pending_since_.reset();
    return Change::kNone;
  }
  if (!pending_since_) pending_since_ = t;
  const double hold = active_ ? options_.clear_after_s : options_.raise_after_s;
  if (t - *pending_since_ < hold) return Change::kNone;
  active_ = !active_;
  pending_since_.reset();
  return active_ ? Change::kRaised : Change::kCleared;
}

}  // namespace fleetloc::fleet
