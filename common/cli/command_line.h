// Command-line parsing by the project's conventions, for fleetctl and every service:
// `--version` prints "<program> <version>" and exits 0, `--help` exits 0, and every usage error
// (unknown flag or subcommand, missing or malformed value: any CLI11 parse error) prints one
// message on stderr and exits 2 — with "did you mean" when a subcommand name is mistyped.
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <string>

namespace fleetloc::cli {

// The project's version (CMake's PROJECT_VERSION).
const char* Version();

// Adds --version to `app` (call before parsing; ParseCommandLine does).
void AddVersionFlag(CLI::App& app, const std::string& program);

// Parses argv into `app`. nullopt: parsed, go on; else the process should exit with that status
// (0 after --help or --version, 2 after a usage error, which has been printed).
std::optional<int> ParseCommandLine(CLI::App& app, const std::string& program, int argc,
                                    char** argv);

}  // namespace fleetloc::cli
