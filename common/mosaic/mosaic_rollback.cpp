// Rolling a mosaic back (see mosaic_rollback.h).
#include "mosaic/mosaic_rollback.h"

#include <string>
#include <utility>

namespace fleetloc::mosaic {

Result<RollbackResult> RollBackMosaic(TileStore& store, long long to_version, bool dry_run) {
  Result<long long> current = store.Refresh();
  if (!current.ok()) return current.status();
  RollbackResult result;
  result.from_version = result.new_version = *current;
  result.to_version = to_version;
  if (to_version < 1 || to_version >= *current) {
    return InvalidInput("rollback: version " + std::to_string(to_version) +
                        " is not an earlier version (the mosaic is at version " +
                        std::to_string(*current) + ")");
  }
  Result<std::vector<TileKey>> changed = store.TilesChangedAfter(to_version);
  if (!changed.ok()) return changed.status();
  std::vector<std::pair<TileKey, std::vector<std::uint8_t>>> restored;
  for (const TileKey& key : *changed) {
    Result<std::vector<std::uint8_t>> bytes = store.ReadTileBytesAt(key, to_version);
    if (!bytes.ok()) {
      return InvalidInput("rollback: tile " + ToString(key) + " as of version " +
                          std::to_string(to_version) +
                          " is no longer stored (pruned, or the tile did not exist then)");
    }
    result.tiles.push_back(key);
    if (!dry_run) restored.emplace_back(key, std::move(bytes).value());
  }
  if (dry_run || restored.empty()) return result;
  FLEETLOC_RETURN_IF_ERROR(store.BeginVersion());
  if (store.version() != *current) {  // BeginVersion read the committed version again
    (void)store.AbortVersion();
    return InvalidInput("rollback: the mosaic changed to version " +
                        std::to_string(store.version()) + " meanwhile; nothing written, run again");
  }
  for (const auto& [key, bytes] : restored) {
    if (Status put = store.PutTileBytes(key, bytes); !put.ok()) {
      (void)store.AbortVersion();
      return put;
    }
  }
  Result<long long> committed = store.CommitVersion();
  if (!committed.ok()) return committed.status();
  result.new_version = *committed;
  return result;
}

}  // namespace fleetloc::mosaic
