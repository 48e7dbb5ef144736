// Per-vehicle reputation from the map server's verdicts on its patches: a vehicle whose recent
// patches keep failing admission (a broken camera or calibration, or a hostile sender) is
// quarantined — its patches are then refused on arrival and never folded — until a maintainer
// releases it. Pure bookkeeping; the map server persists the standing in the mosaic file.
#pragma once

#include <string>

namespace fleetloc::mapping {

struct ReputationOptions {
  int window = 16;                     // recent verdicts remembered per vehicle
  int min_judged = 6;                  // no quarantine on fewer recent verdicts than this
  double max_refused_fraction = 0.75;  // quarantine above this share of refusals in the window
};

// "" or the option that is out of range.
std::string OptionsProblem(const ReputationOptions& options);

struct VehicleStanding {
  long long admitted = 0;  // all time
  long long refused = 0;   // all time
  std::string recent;      // 'A' (admitted) / 'R' (refused), oldest first, at most `window`
  bool quarantined = false;
  std::string reason;  // why it was quarantined (the last refusal's reason and the counts)
  int recent_refused() const;
};

// Adds one verdict (`refusal_reason` empty when admitted). Returns true when this verdict put the
// vehicle in quarantine (false if it already was, or is not now).
bool RecordVerdict(VehicleStanding* standing, bool admitted, const std::string& refusal_reason,
                   const ReputationOptions& options);

// Lifts the quarantine and forgets the recent verdicts (the all-time counts stay).
void Release(VehicleStanding* standing);

}  // namespace fleetloc::mapping
