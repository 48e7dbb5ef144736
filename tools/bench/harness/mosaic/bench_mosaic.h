// `fleetctl bench mosaic`, one image size: compose a real-texture floor of that size (streamed
// PGM), import it with the real importer, and time lookups in the resulting mosaic in rounds. Each
// step runs in its own child process, so its time and peak RSS are its own.
#pragma once

#include <cstdint>
#include <filesystem>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "base/status.h"
#include "harness/common/forked_step.h"
#include "harness/mosaic/mosaic_lookups.h"

namespace fleetloc::bench {

struct MosaicBenchSettings {
  std::vector<std::string> photos;  // floor photographs the source floor is composed from
  std::filesystem::path work_dir;   // one subdirectory per size
  int block_px = 512;               // composition block side
  std::uint64_t seed = 1;           // composition and lookup sampling
  double resolution_m = 0.0005;
  bool keep_files = false;  // keep each size's PGM and mosaic (else removed once measured)
  LookupSettings lookups;   // of one round (its seed is replaced by the round's)
};

struct MosaicSizeBench {
  cv::Size size_px;
  std::filesystem::path pgm, mosaic;
  double megapixels() const { return size_px.area() / 1e6; }
  ChildRun compose;                // writing the source PGM
  ChildRun import;                 // mosaic::ImportImage of that PGM
  ChildRun lookup;                 // the lookup rounds: times summed, the largest peak RSS
  long long caller_rss_bytes = 0;  // this process's RSS when it forked the import (inherited)
  std::uintmax_t pgm_bytes = 0, mosaic_bytes = 0;
  LookupRun lookups;  // every round's samples
};

// Composes the size's floor into its work subdirectory and imports it, each in a child process.
// The files stay for the lookup rounds. InvalidInput for photos the composer rejects; Internal on
// I/O or child process failures.
Result<MosaicSizeBench> ComposeAndImport(cv::Size size_px, const MosaicBenchSettings& settings);

// Times lookup round `round` (its own seed) in the size's mosaic, in a child process, and adds its
// samples and usage to `bench`. Internal if a read fails.
Status AddLookupRound(const MosaicBenchSettings& settings, int round, MosaicSizeBench* bench);

// Removes the size's PGM and mosaic unless settings.keep_files.
void RemoveSizeFiles(const MosaicBenchSettings& settings, const MosaicSizeBench& bench);

}  // namespace fleetloc::bench
