// Test helpers for the run_io tests: a gray PNG, a valid run directory, and (re-exported from
// io/io_test_util.h) the temporary directory, small files and the one-line error format check.
#pragma once

#include <filesystem>

#include "io/io_test_util.h"
#include "run_io/run.h"

namespace fleetloc::run_io::testing {

using io::testing::HasError;
using io::testing::ReadText;
using io::testing::TempDir;
using io::testing::WriteText;

// Writes a width×height 8-bit gray PNG with a deterministic pattern.
void WriteGrayPng(const std::filesystem::path& path, int width, int height);

// A valid run of 3 frames (t = 0, 0.1, 0.2; 16×12 px images img/f<i>.png), 5 odometry samples
// (t = 0 … 0.2 every 0.05) and truth, written into `dir` with WriteRun and returned.
Run WriteValidRun(const std::filesystem::path& dir);

}  // namespace fleetloc::run_io::testing
