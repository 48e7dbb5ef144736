// Rolling a mosaic back to an earlier version: a new version whose tiles are those the mosaic
// showed at the earlier one (every tile changed since, at every level), so vehicles and tools
// that follow versions see it like any other change, and the undone versions stay in the file
// until retention removes them. Patches folded into the undone versions stay marked folded: the
// pixels go back, a later re-map does not fold those patches again. A dry run only lists the
// tiles it would write.
#pragma once

#include <vector>

#include "base/status.h"
#include "mosaic/tile_key.h"
#include "mosaic/tile_store.h"

namespace fleetloc::mosaic {

struct RollbackResult {
  long long from_version = 0;  // the version current before
  long long to_version = 0;    // the version restored
  long long new_version = 0;   // the version written (from_version on a dry run)
  std::vector<TileKey> tiles;  // tiles written, or that would be
};

// InvalidInput when `to_version` is not an earlier version (1 .. current − 1), when a tile's
// content at `to_version` is no longer stored (pruned: `fleetctl mosaic prune` keeps the last
// few versions), or when another writer commits while the rollback runs (then nothing is
// written: run it again); Internal on storage errors. `store` must be writable unless dry_run.
Result<RollbackResult> RollBackMosaic(TileStore& store, long long to_version, bool dry_run);

}  // namespace fleetloc::mosaic
