// Whole-file reading and atomic (write-to-temporary-then-rename) writing for the io adapters.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "base/status.h"

namespace fleetloc::io {

// Reads the whole file. NotFound "<path>: not found" when it does not exist (or is not a regular
// file); Internal when it exists but cannot be read.
Result<std::string> ReadFileText(const std::filesystem::path& path);

// `dir` made absolute and lexically normal, without a trailing separator ("/a/b/" → "/a/b").
std::filesystem::path AbsoluteDir(const std::filesystem::path& dir);

// Writes `content` to a temporary file beside `path`, then renames it over `path`, so a reader
// never sees a half-written file. Creates missing parent directories. Internal (naming the path) on
// any I/O failure; the temporary file is removed on failure.
Status WriteFileAtomically(const std::filesystem::path& path, std::string_view content);

// Raises this process's soft limit of open files to its hard limit (a server holding thousands of
// connections needs more than the usual 1024). Returns the soft limit now in force.
long RaiseOpenFileLimit();

}  // namespace fleetloc::io
