// (being written in this session)
#include "commands.h"

namespace fleetloc::fleetctl {
void RegisterSimCommand(CLI::App&, Status*) {}
}  // namespace fleetloc::fleetctl
