// The map-matching files of docs/formats.md: landmarks.csv (`id,x,y`, the landmark map) and
// points.csv
// (`x,y`, measured floor points placed in the map frame). Errors name file, line and field.
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

#include "base/status.h"

namespace fleetloc::run_io {

struct LandmarkMap {
  std::vector<std::string> ids;            // as written; unique and non-empty
  std::vector<Eigen::Vector2d> positions;  // metres in `map`; no two closer than 1 µm
};

// Reads landmarks.csv. NotFound when missing; InvalidInput "<file>:<line>: field '<name>': ..."
// for a wrong header, an empty id, a non-finite coordinate, an id used twice or a position listed
// twice (mapmatch::kSameLandmarkM), naming the later line and the earlier one.
Result<LandmarkMap> ReadLandmarksCsv(const std::filesystem::path& path);

// Reads points.csv (any number of rows, repeats allowed). Errors as ReadLandmarksCsv.
Result<std::vector<Eigen::Vector2d>> ReadPointsCsv(const std::filesystem::path& path);

}  // namespace fleetloc::run_io
