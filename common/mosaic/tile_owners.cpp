// Tile ownership across map servers.
#include "mosaic/tile_owners.h"

#include <algorithm>

namespace fleetloc::mosaic {

std::vector<std::string> TileOwners::OwnersOf(const TileKey& key) const {
  std::vector<std::string> owners;
  for (const auto& [server, owned] : owned_) {
    if (owned.Owns(key)) owners.push_back(server);
  }
  return owners;
}

std::vector<int> TileOwners::OwnerCounts(const MosaicLayout& layout) const {
  const int cols = TileColumns(layout, 0), rows = TileRows(layout, 0);
  std::vector<int> counts(static_cast<size_t>(cols) * rows, 0);
  for (const auto& [server, owned] : owned_) {
    for (int row = std::max(0, owned.row_begin); row < std::min(rows, owned.row_end); ++row) {
      for (int col = std::max(0, owned.col_begin); col < std::min(cols, owned.col_end); ++col) {
        ++counts[static_cast<size_t>(row) * cols + col];
      }
    }
  }
  return counts;
}

long long TileOwners::UncoveredTiles(const MosaicLayout& layout) const {
  const std::vector<int> counts = OwnerCounts(layout);
  return std::count(counts.begin(), counts.end(), 0);
}

long long TileOwners::OverlappingTiles(const MosaicLayout& layout) const {
  const std::vector<int> counts = OwnerCounts(layout);
  return std::count_if(counts.begin(), counts.end(), [](int n) { return n > 1; });
}

}  // namespace fleetloc::mosaic
