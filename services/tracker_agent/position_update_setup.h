// The agent's global position update for a replayed run, set up at start: the run's forward
// camera (forward/, docs/formats.md) and the landmark map (docs/formats.md: the configured
// `landmarks` file, else the run's own landmarks.csv), both read and validated before the agent
// starts.
#pragma once

#include <memory>

#include "base/status.h"
#include "run_io/run.h"
#include "tracker_agent/agent_config.h"
#include "tracker_agent/agent_position_update.h"

namespace fleetloc::tracker_agent {

// The position update's options from the configuration (period, window, weight half-life).
PositionUpdateOptions PositionUpdateOptionsFrom(const AgentConfig& config);

// nullptr (and a log line saying why) when the run has no forward camera or no landmark map is
// configured or in the run; NotFound for a configured landmark file that is missing, and the
// reader's InvalidInput "<file>:<line>: field '<name>': ..." for a broken one.
Result<std::unique_ptr<AgentPositionUpdate>> PositionUpdateForRun(const AgentConfig& config,
                                                                  const run_io::Run& run);

}  // namespace fleetloc::tracker_agent
