// `fleetctl bench mosaic`, one image size: compose a real-texture floor of that size (streamed
// PGM), import it with the real importer, and time lookups in the resulting mosaic. Each of the
// three steps runs in its own child process, so its time and peak RSS are its own.
#pragma once

#include <cstdint>
#include <filesystem>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "base/status.h"
#include "child_process.h"
#include "mosaic_lookups.h"

namespace fleetloc::fleetctl {

struct MosaicBenchSettings {
  std::vector<std::string> photos;  // floor photographs the source floor is composed from
  std::filesystem::path work_dir;   // one subdirectory per size
  int block_px = 512;               // composition block side
  std::uint64_t seed = 1;           // composition and lookup sampling
  double resolution_m = 0.0005;
  bool keep_files = false;  // keep each size's PGM and mosaic (else removed once measured)
  LookupSettings lookups;
};

struct MosaicSizeBench {
  cv::Size size_px;
  double megapixels() const { return size_px.area() / 1e6; }
  ChildRun compose;                // writing the source PGM
  ChildRun import;                 // mosaic::ImportImage of that PGM
  ChildRun lookup;                 // MeasureLookups
  long long caller_rss_bytes = 0;  // this process's RSS when it forked the import (inherited)
  std::uintmax_t pgm_bytes = 0, mosaic_bytes = 0;
  LookupTimes times;
};

// Benchmarks one size. InvalidInput for photos or sizes the composer rejects; Internal on I/O or
// child process failures.
Result<MosaicSizeBench> BenchMosaicSize(cv::Size size_px, const MosaicBenchSettings& settings);

}  // namespace fleetloc::fleetctl
