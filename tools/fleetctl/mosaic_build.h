// `fleetctl mosaic build` (docs/cli.md): the file side of building a mosaic from a mapping run —
// read the run (docs/formats.md), interpolate odometry at the frame times, hand frames to the
// mapping library for registration and the pose graph, blend, and write the rows through the
// importer's .partial path as version 1 of a new tile store. Progress goes to spdlog.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "base/status.h"
#include "mapping/mosaic_blender.h"
#include "mapping/run_mapper.h"
#include "mosaic/raster_source.h"

namespace fleetloc::fleetctl {

struct MosaicBuildOptions {
  mapping::MapperOptions mapper;
  mapping::BlendOptions blend;
};

// Mapped camera poses against the run's truth.csv (camera_ground positions, level-0 pixels).
struct MappedAccuracy {
  double camera_position_rms_px = 0.0;
  double camera_position_max_px = 0.0;
  double heading_rms_rad = 0.0;
};

struct MosaicBuildSummary {
  int frames = 0;
  mapping::MappedRun mapped;
  mapping::Canvas canvas;
  std::size_t canvas_bytes = 0;
  mosaic::MosaicLayout layout;
  std::optional<MappedAccuracy> accuracy;  // when the run has truth.csv
  double mapping_s = 0.0, blending_s = 0.0, writing_s = 0.0;
};

// Builds `out_db` from the run in `run_dir`. NotFound / InvalidInput (exit status 2) naming the
// file, line and field for a run that breaks docs/formats.md, an unreadable frame, or a run whose
// frames cannot be registered; InvalidInput if `out_db` exists; Internal on I/O errors.
Result<MosaicBuildSummary> BuildMosaicFromRun(const std::filesystem::path& run_dir,
                                              const std::string& out_db,
                                              const MosaicBuildOptions& options);

nlohmann::ordered_json BuildSummaryJson(const MosaicBuildSummary& summary);

}  // namespace fleetloc::fleetctl
