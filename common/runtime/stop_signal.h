// SIGINT/SIGTERM → a stop flag every daemon's main loop polls, so each stops cleanly (closes its
// DDS entities and SQLite files) instead of dying mid-write.
#pragma once

#include <atomic>

namespace fleetloc::runtime {

// Installs handlers for SIGINT and SIGTERM that set the returned flag (idempotent). A second
// signal while stopping restores the default action, so a third one kills a stuck process.
const std::atomic<bool>& InstallStopSignals();

}  // namespace fleetloc::runtime
