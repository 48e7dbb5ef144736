// Demo floor directory lookup for the benchmarks.
#include "harness/common/bench_paths.h"

#include <spdlog/spdlog.h>

#include "mosaic/importer.h"
#include "support/floor_images.h"

namespace fleetloc::bench {

Result<std::string> EnsureDemoMosaic(const std::string& work_dir, const std::string& image_name,
                                     const std::string& db_name) {
  const std::filesystem::path db = std::filesystem::path(work_dir) / db_name;
  if (std::filesystem::exists(db)) return db.string();
  mosaic::ImportOptions options;
  options.resolution_m = 0.0005;
  const std::filesystem::path image = fleetctl::DefaultFloorsDir() / image_name;
  spdlog::info("bench: importing {} into {}", image.string(), db.string());
  auto imported = mosaic::ImportImage(image.string(), options, db.string());
  if (!imported.ok()) return imported.status();
  return db.string();
}

}  // namespace fleetloc::bench
