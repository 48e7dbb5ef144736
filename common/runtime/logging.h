// Process-wide logging setup: every fleetloc program logs through spdlog's default logger.
#pragma once

#include <string>

namespace fleetloc::runtime {

// Makes a thread-safe spdlog logger that writes to stderr, named `name` (the vehicle id or the
// service name; "fleetloc" when empty), and installs it as spdlog's default logger, so that
// spdlog::info(...) lines read "[time] [agv-7] [info] ...". Levels come from the SPDLOG_LEVEL
// environment variable (e.g. SPDLOG_LEVEL=debug), default info. Calling it again replaces the
// default logger; it never throws.
void SetupLogging(const std::string& name);

}  // namespace fleetloc::runtime
