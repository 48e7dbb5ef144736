// Retention in a mosaic file: old tile versions and stored patches are deleted so the file stops
// growing. Kept: every tile row needed to serve the last `tile_versions_kept` mosaic versions (the
// current one included), their place indexes, and every patch that is not yet folded (or refused)
// unless it waited longer than `unfolded_patch_retention_s`; folded and refused patches go after
// `patch_retention_s` (from when the server stored them). One transaction; safe while the map
// server runs (it serves the current version). SQLite reuses the freed pages; `vacuum` also gives
// them back to the file system (it rewrites the file: slow, and needs as much free disk again).
#pragma once

#include <string>

#include "base/status.h"

namespace fleetloc::mosaic {

struct RetentionPolicy {
  int tile_versions_kept = 8;
  double patch_retention_s = 7 * 86400.0;
  double unfolded_patch_retention_s = 90 * 86400.0;
};

// "" or the field out of range.
std::string RetentionProblem(const RetentionPolicy& policy);

struct PruneResult {
  long long mosaic_version = 0;  // committed when pruning
  long long oldest_version_kept = 0;
  long long tile_rows_deleted = 0;
  long long patches_deleted = 0;
  long long patch_bytes_deleted = 0;
  long long place_indexes_deleted = 0;
  long long file_bytes_before = 0, file_bytes_after = 0;
};

// Prunes the mosaic file at `path` by `policy` at wall-clock time `now_s` (seconds since the
// epoch). NotFound / InvalidInput naming the file; Internal on SQLite errors (nothing deleted
// then).
Result<PruneResult> PruneMosaic(const std::string& path, const RetentionPolicy& policy,
                                double now_s, bool vacuum = false);

}  // namespace fleetloc::mosaic
