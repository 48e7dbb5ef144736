// Test helpers for the io tests (and, through run_io/run_io_test_util.h, the run_io tests): a
// temporary directory per test, small files, and checks of the one-line
// "<file>:<line>: field '<name>': ..." error format.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "base/status.h"

namespace fleetloc::io::testing {

// A fresh directory under the system temp dir, removed with its content on destruction.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

// Writes `text` to `path` (creating parent directories).
void WriteText(const std::filesystem::path& path, const std::string& text);
std::string ReadText(const std::filesystem::path& path);

// Asserts `status` has `code` and a one-line message starting "<file>:<line>: field '<field>': ".
// line <= 0 means the message has no line; an empty field means it names no field.
::testing::AssertionResult HasError(const Status& status, StatusCode code,
                                    const std::filesystem::path& file, int line,
                                    const std::string& field);

}  // namespace fleetloc::io::testing
