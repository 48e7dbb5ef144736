// (being written in this session)
#include "commands.h"

namespace fleetloc::fleetctl {
void RegisterMosaicCommands(CLI::App&, Status*) {}
}  // namespace fleetloc::fleetctl
