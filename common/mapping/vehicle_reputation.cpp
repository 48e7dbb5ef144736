// Sliding-window reputation and quarantine decision.
#include "mapping/vehicle_reputation.h"

#include <algorithm>

namespace fleetloc::mapping {

std::string OptionsProblem(const ReputationOptions& o) {
  if (o.window < 1 || o.window > 1024) return "window must be in [1, 1024]";
  if (o.min_judged < 1 || o.min_judged > o.window) return "min_judged must be in [1, window]";
  if (!(o.max_refused_fraction >= 0 && o.max_refused_fraction < 1)) {
    return "max_refused_fraction must be in [0, 1)";
  }
  return "";
}

int VehicleStanding::recent_refused() const {
  return static_cast<int>(std::count(recent.begin(), recent.end(), 'R'));
}

bool RecordVerdict(VehicleStanding* s, bool admitted, const std::string& refusal_reason,
                   const ReputationOptions& o) {
  ++(admitted ? s->admitted : s->refused);
  s->recent.push_back(admitted ? 'A' : 'R');
  if (static_cast<int>(s->recent.size()) > o.window) {
    s->recent.erase(0, s->recent.size() - static_cast<size_t>(o.window));
  }
  if (s->quarantined || static_cast<int>(s->recent.size()) < o.min_judged) return false;
  const int refused = s->recent_refused();
  if (refused <= o.max_refused_fraction * static_cast<double>(s->recent.size())) return false;
  s->quarantined = true;
  s->reason = std::to_string(refused) + " of its last " + std::to_string(s->recent.size()) +
              " patches refused (last: " + (refusal_reason.empty() ? "admitted" : refusal_reason) +
              ")";
  return true;
}

void Release(VehicleStanding* s) {
  s->quarantined = false;
  s->reason.clear();
  s->recent.clear();
}

}  // namespace fleetloc::mapping
