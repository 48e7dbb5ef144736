// TileStore: the mosaic as a versioned tile pyramid in one SQLite file (MBTiles-like tables
// `metadata(name, value)` and `tiles(level, col, row, version, data)`). WAL mode: one writer, many
// readers. A new version of any number of tiles becomes visible atomically with the bump of the
// mosaic version, so a crash never exposes a half-written version.
#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <vector>

#include "base/status.h"
#include "mosaic/mosaic_metadata.h"
#include "mosaic/mosaic_view.h"
#include "mosaic/raster_source.h"
#include "mosaic/tile_key.h"
#include "sqlite/sqlite_util.h"

namespace fleetloc::mosaic {

enum class OpenMode { kReadOnly, kReadWrite };

class TileStore {
 public:
  // Creates a new, empty mosaic file (version 0, no tiles) with `layout`'s geometry; an empty
  // mosaic_id is replaced by a fresh random one. InvalidInput if the file exists or the layout is
  // invalid; Internal on SQLite failure.
  static Result<std::unique_ptr<TileStore>> Create(const std::string& path, MosaicLayout layout);

  // Opens an existing mosaic. NotFound if there is no such file; InvalidInput naming the file and
  // the problem if it is not a fleetloc mosaic (not SQLite, truncated, no or wrong metadata).
  static Result<std::unique_ptr<TileStore>> Open(const std::string& path, OpenMode mode);

  ~TileStore();  // rolls back a version that was begun but not committed
  TileStore(const TileStore&) = delete;
  TileStore& operator=(const TileStore&) = delete;

  const std::string& path() const { return path_; }
  // The layout; its version is the last committed version this handle knows (see Refresh).
  MosaicLayout layout() const;
  long long version() const;

  // The newest stored version <= version() of a tile, as PNG bytes / decoded. NotFound if the
  // mosaic has no such tile; InvalidInput if the stored bytes do not decode to a tile.
  Result<std::vector<std::uint8_t>> ReadTileBytes(const TileKey& key);
  // The same as the mosaic showed it at an earlier `version` (NotFound when no row of the tile
  // that old is stored: pruned, or the tile did not exist yet).
  Result<std::vector<std::uint8_t>> ReadTileBytesAt(const TileKey& key, long long version);
  // Every tile (all levels) with a stored version after `version`, up to version().
  Result<std::vector<TileKey>> TilesChangedAfter(long long version);
  Result<cv::Mat> ReadTile(const TileKey& key);

  // Starts writing version version()+1 (of the newest committed state) in one write transaction.
  // Only one version may be open at a time (checked). InvalidInput on a read-only store.
  Status BeginVersion();
  // Stores a tile (CV_8UC1, tile_size square) / its PNG bytes in the open version. InvalidInput if
  // the key is outside the level's tile grid or the tile has the wrong size or type.
  Status PutTile(const TileKey& key, const cv::Mat& tile);
  Status PutTileBytes(const TileKey& key, std::span<const std::uint8_t> png);
  // Bumps the mosaic version and commits it together with the tiles; returns the new version.
  // On failure everything of the version is rolled back.
  Result<long long> CommitVersion();
  // Discards the open version.
  Status AbortVersion();

  // Re-reads the committed mosaic version (e.g. after a TileUpdate announcement); returns it.
  Result<long long> Refresh();

  // Number of distinct tiles visible at version(), per level 0 .. levels-1.
  Result<std::vector<long long>> TileCountsPerLevel();
  // The whole metadata table.
  Result<Metadata> ReadMetadata();

  // SQLite's query plan (EXPLAIN QUERY PLAN details, "; "-joined) for the tile lookup ReadTileBytes
  // runs, e.g. "SEARCH tiles USING INDEX sqlite_autoindex_tiles_1 (level=? AND col=? AND row=? AND
  // version<?)": shows the lookup is an index search, O(log tiles), not a scan.
  Result<std::string> TileLookupPlan();

 private:
  TileStore(std::string path, sqlite::Db db, OpenMode mode);
  Status Init(const std::string& problem_prefix);
  Result<Metadata> ReadMetadataLocked();
  Result<long long> ReadCommittedVersionLocked();
  Status CheckKey(const TileKey& key) const;

  const std::string path_;
  const OpenMode mode_;
  mutable std::mutex mutex_;
  sqlite::Db db_;  // declared before the statements: destroyed after them
  sqlite::Stmt select_tile_;
  sqlite::Stmt insert_tile_;
  sqlite::Stmt select_version_;
  sqlite::Stmt update_version_;
  MosaicLayout layout_;
  long long pending_version_ = -1;  // >= 0 while a version is open
};

// A TileLoader (for MosaicView) reading decoded tiles from a store it keeps alive.
TileLoader MakeTileLoader(std::shared_ptr<TileStore> store);

}  // namespace fleetloc::mosaic
