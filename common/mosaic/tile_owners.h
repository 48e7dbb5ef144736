// Which map servers answer for which tiles when one mosaic is served by several servers, each
// owning a rectangle of level-0 tiles (TileOwnership, from its MosaicInfo). A vehicle uses it to
// know whose silence makes a tile unreachable, and to check that the servers cover the grid.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "mosaic/tile_key.h"
#include "mosaic/tile_ownership.h"

namespace fleetloc::mosaic {

class TileOwners {
 public:
  // Sets (or replaces) the range `server_id` owns.
  void Set(const std::string& server_id, const TileOwnership& owned) { owned_[server_id] = owned; }
  void Remove(const std::string& server_id) { owned_.erase(server_id); }

  // Every server owning `key`, in server id order (more than one only where ranges overlap).
  std::vector<std::string> OwnersOf(const TileKey& key) const;
  // The number of level-0 tiles of `layout` no server owns.
  long long UncoveredTiles(const MosaicLayout& layout) const;
  // The number of level-0 tiles of `layout` more than one server owns.
  long long OverlappingTiles(const MosaicLayout& layout) const;

  size_t servers() const { return owned_.size(); }
  const std::map<std::string, TileOwnership>& ranges() const { return owned_; }

 private:
  // How many servers own each level-0 tile, row-major.
  std::vector<int> OwnerCounts(const MosaicLayout& layout) const;

  std::map<std::string, TileOwnership> owned_;
};

}  // namespace fleetloc::mosaic
