// The place-index cache table: absent until written, one blob per (version, key), older versions
// replaced, missing files reported.
#include "mosaic/place_index_store.h"

#include <gtest/gtest.h>

#include "mosaic/test_util.h"
#include "mosaic/tile_store.h"

namespace fleetloc::mosaic {
namespace {

using testing::ScratchDir;

std::string NewMosaic(const ScratchDir& dir) {
  MosaicLayout layout;
  layout.width_px = layout.height_px = 100;
  layout.geo.resolution = 0.001;
  EXPECT_TRUE(TileStore::Create(dir.File("m.db"), layout).ok());
  return dir.File("m.db");
}

TEST(PlaceIndexStore, StoresOneBlobPerVersionAndKeyAndDropsOlderVersions) {
  ScratchDir dir;
  const std::string path = NewMosaic(dir);
  auto absent = ReadPlaceIndexBlob(path, 1, "orb");
  ASSERT_TRUE(absent.ok()) << absent.status().message();
  EXPECT_FALSE(absent->has_value());
  const std::vector<std::uint8_t> v1{1, 2, 3}, v2{4, 5, 6, 7}, other{9};
  ASSERT_TRUE(WritePlaceIndexBlob(path, 1, "orb", v1).ok());
  ASSERT_TRUE(WritePlaceIndexBlob(path, 1, "other", other).ok());
  EXPECT_EQ(ReadPlaceIndexBlob(path, 1, "orb")->value(), v1);
  ASSERT_TRUE(WritePlaceIndexBlob(path, 2, "orb", v2).ok());
  EXPECT_EQ(ReadPlaceIndexBlob(path, 2, "orb")->value(), v2);
  EXPECT_FALSE(ReadPlaceIndexBlob(path, 1, "orb")->has_value());  // replaced by version 2
  EXPECT_EQ(ReadPlaceIndexBlob(path, 1, "other")->value(), other);
}

TEST(PlaceIndexStore, MissingFileIsNotFound) {
  ScratchDir dir;
  EXPECT_EQ(ReadPlaceIndexBlob(dir.File("none.db"), 1, "k").status().code(), StatusCode::kNotFound);
  EXPECT_EQ(WritePlaceIndexBlob(dir.File("none.db"), 1, "k", std::vector<std::uint8_t>{1}).code(),
            StatusCode::kNotFound);
}

}  // namespace
}  // namespace fleetloc::mosaic
