// fleetctl bench agent: the tracker agent's cycle time on the live path (a tracker_agent process
// fed by a map_server process over DDS, replaying as fast as it can) next to the offline tracker
// (`fleetctl track`'s replay) on the same simulated run over a demo floor.
#pragma once

#include <string>

#include "base/status.h"

namespace fleetloc::bench {

struct AgentBenchSettings {
  std::string work_dir;
  int frames = 1000;
  int domain = 92;
  std::string json;
};

Status RunAgentBench(const AgentBenchSettings& settings);

}  // namespace fleetloc::bench
