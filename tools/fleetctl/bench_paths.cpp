// Demo floor directory lookup for the benchmarks.
#include "bench_paths.h"

namespace fleetloc::fleetctl {

std::filesystem::path DefaultFloorsDir() {
  namespace fs = std::filesystem;
  constexpr const char* kFloorsSubdir = "deploy/demo/floors";
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  const fs::path beside = exe.parent_path().parent_path().parent_path() / kFloorsSubdir;
  if (!ec && fs::is_directory(beside, ec)) return beside;
  return fs::path(FLEETLOC_SOURCE_DIR) / kFloorsSubdir;
}

}  // namespace fleetloc::fleetctl
