// (being written in this session)
#include "commands.h"

namespace fleetloc::fleetctl {
void RegisterBenchCommand(CLI::App&, Status*) {}
}  // namespace fleetloc::fleetctl
