// The place index cache of a mosaic file: built once and then loaded (equal features), rebuilt
// for a corrupt cached blob or on request, never stored when told to ignore the cache, and the
// build's error for a floor without features.
#include "mosaic_upkeep/place_index_cache.h"

#include <gtest/gtest.h>

#include "mosaic/importer.h"
#include "mosaic/mosaic_view.h"
#include "mosaic/place_index_store.h"
#include "mosaic/test_util.h"
#include "mosaic/tile_store.h"

namespace fleetloc::mosaic_upkeep {
using mosaic::ImportImage;
using mosaic::ImportOptions;
using mosaic::MakeTileLoader;
using mosaic::MosaicLayout;
using mosaic::MosaicView;
using mosaic::OpenMode;
using mosaic::ReadPlaceIndexBlob;
using mosaic::TileCache;
using mosaic::TileStore;
using mosaic::WritePlaceIndexBlob;
namespace {

using mosaic::testing::ScratchDir;
using mosaic::testing::SourcePath;

// A mosaic imported from the 0.5 m gravel photo, and a view over it.
struct GravelMosaic {
  explicit GravelMosaic(const ScratchDir& dir,
                        const std::string& image = "deploy/demo/floors/gravel_1024.png")
      : path(dir.File("m.db")) {
    ImportOptions options;
    options.resolution_m = 0.0005;
    const Result<MosaicLayout> imported = ImportImage(SourcePath(image), options, path);
    EXPECT_TRUE(imported.ok()) << imported.status().message();
    auto store = TileStore::Open(path, OpenMode::kReadOnly);
    EXPECT_TRUE(store.ok());
    std::shared_ptr<TileStore> shared = std::move(store).value();
    view = std::make_unique<MosaicView>(shared->layout(), MakeTileLoader(shared),
                                        std::make_shared<TileCache>(std::size_t{16} << 20));
  }
  std::string path;
  std::unique_ptr<MosaicView> view;
};

TEST(PlaceIndexCache, BuildsOnceThenLoadsTheSameIndex) {
  ScratchDir dir;
  GravelMosaic mosaic(dir);
  const relocalization::PlaceIndexOptions options;
  auto built = LoadOrBuildPlaceIndex(mosaic.path, *mosaic.view, options, IndexCache::kUse);
  ASSERT_TRUE(built.ok()) << built.status().message();
  EXPECT_FALSE(built->from_cache);
  EXPECT_GT(built->index.size(), 100u);
  EXPECT_EQ(built->blob, built->index.Serialize());
  auto loaded = LoadOrBuildPlaceIndex(mosaic.path, *mosaic.view, options, IndexCache::kUse);
  ASSERT_TRUE(loaded.ok());
  EXPECT_TRUE(loaded->from_cache);
  EXPECT_EQ(loaded->blob, built->blob);
  ASSERT_EQ(loaded->index.size(), built->index.size());
  EXPECT_EQ(loaded->index.position_m(7), built->index.position_m(7));
  auto rebuilt = LoadOrBuildPlaceIndex(mosaic.path, *mosaic.view, options, IndexCache::kRebuild);
  ASSERT_TRUE(rebuilt.ok());
  EXPECT_FALSE(rebuilt->from_cache);
}

TEST(PlaceIndexCache, ACorruptCachedIndexIsRebuiltAndIgnoringTheCacheStoresNothing) {
  ScratchDir dir;
  GravelMosaic mosaic(dir);
  const relocalization::PlaceIndexOptions options;
  auto ignored = LoadOrBuildPlaceIndex(mosaic.path, *mosaic.view, options, IndexCache::kIgnore);
  ASSERT_TRUE(ignored.ok());
  EXPECT_FALSE(ReadPlaceIndexBlob(mosaic.path, 1, PlaceIndexKey(options))->has_value());
  std::vector<std::uint8_t> corrupt = ignored->blob;
  corrupt[corrupt.size() / 2] ^= 0xFF;
  ASSERT_TRUE(WritePlaceIndexBlob(mosaic.path, 1, PlaceIndexKey(options), corrupt).ok());
  auto repaired = LoadOrBuildPlaceIndex(mosaic.path, *mosaic.view, options, IndexCache::kUse);
  ASSERT_TRUE(repaired.ok()) << repaired.status().message();
  EXPECT_FALSE(repaired->from_cache);
  EXPECT_EQ(ReadPlaceIndexBlob(mosaic.path, 1, PlaceIndexKey(options))->value(), ignored->blob);
}

TEST(PlaceIndexCache, KeysDifferWithTheOptions) {
  relocalization::PlaceIndexOptions a, b;
  b.features.cell_px += 8;
  EXPECT_NE(PlaceIndexKey(a), PlaceIndexKey(b));
}

}  // namespace
}  // namespace fleetloc::mosaic_upkeep
