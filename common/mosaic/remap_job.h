// A re-mapping job against the stored mosaic (the map server's, and any tool's): select the
// unfolded patches of a region, compute the new tiles (mapping::ComputeRemap), then mark the
// patches and commit the tiles as the next mosaic version. A job that fails, is cancelled or dies
// at any point leaves the previous version intact, and can simply be run again.
#pragma once

#include <atomic>
#include <functional>
#include <string>
#include <vector>

#include "base/status.h"
#include "mosaic/patch_store.h"
#include "mosaic/tile_store.h"

namespace fleetloc::mosaic {

enum class RemapMode { kBlend, kReplace };

struct RemapRequest {
  MapRect region;
  RemapMode mode = RemapMode::kBlend;
};

struct RemapProgress {
  std::string phase;  // select, register, blend, pyramid, commit
  int done = 0;
  int total = 0;
};

struct RemapResult {
  long long new_version = 0;          // the previous version when nothing changed
  std::vector<TileKey> changed_tiles;  // every level
  int patches_folded = 0;
  int patches_rejected = 0;           // could not be placed well enough (see mapping::RemapOptions)
  int patches_unreadable = 0;         // stored image did not decode
};

// InvalidInput for an empty, inverted or non-finite region or one outside the mosaic, and when
// cancelled; Internal on storage errors. `store` must be writable.
Result<RemapResult> RunRemap(TileStore& store, PatchStore& patches, const RemapRequest& request,
                             const std::function<void(const RemapProgress&)>& progress = {},
                             const std::atomic<bool>* cancel = nullptr);

}  // namespace fleetloc::mosaic
