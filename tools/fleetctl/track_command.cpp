// (being written in this session)
#include "commands.h"

namespace fleetloc::fleetctl {
void RegisterTrackCommand(CLI::App&, Status*) {}
}  // namespace fleetloc::fleetctl
