// Vehicle standing in the mosaic file: written standings read back exactly after a reopen, an
// unknown vehicle has a fresh standing, and a release lifts the quarantine.
#include "mosaic_upkeep/vehicle_standing_store.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "mosaic/importer.h"
#include "mosaic/test_util.h"

namespace fleetloc::mosaic_upkeep {
using mosaic::ImportImage;
using mosaic::ImportOptions;
namespace {

class VehicleStandingStoreTest : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ = dir_.File("floor.db");
    ImportOptions options;
    options.resolution_m = 0.0005;
    ASSERT_TRUE(ImportImage(FLEETLOC_SOURCE_DIR "/tests/data/gravel.png", options, path_).ok());
  }
  std::unique_ptr<VehicleStandingStore> Open() {
    auto store = VehicleStandingStore::Open(path_);
    EXPECT_TRUE(store.ok()) << store.status().message();
    return std::move(store).value();
  }

  mosaic::testing::ScratchDir dir_;  // removed with the fixture
  std::string path_;
};

TEST_F(VehicleStandingStoreTest, StandingsSurviveAReopenAndAReleaseLiftsTheQuarantine) {
  mapping::VehicleStanding bad{3, 12, "ARRRRRRR", true, "8 of its last 8 patches refused"};
  mapping::VehicleStanding good{40, 1, "AAAR", false, ""};
  ASSERT_TRUE(Open()->PutAll({{"evil", bad}, {"agv-1", good}}).ok());
  auto store = Open();
  auto all = store->All();
  ASSERT_TRUE(all.ok());
  ASSERT_EQ(all->size(), 2u);
  EXPECT_EQ(all->at("evil").refused, 12);
  EXPECT_EQ(all->at("evil").recent, "ARRRRRRR");
  EXPECT_EQ(all->at("evil").reason, "8 of its last 8 patches refused");
  EXPECT_TRUE(*store->IsQuarantined("evil"));
  EXPECT_FALSE(*store->IsQuarantined("agv-1"));
  EXPECT_FALSE(*store->IsQuarantined("agv-9"));  // never seen
  EXPECT_EQ(store->Get("agv-9")->admitted, 0);
  ASSERT_TRUE(store->Release("evil").ok());
  EXPECT_FALSE(*Open()->IsQuarantined("evil"));
  EXPECT_EQ(Open()->Get("evil")->refused, 12);
  EXPECT_EQ(store->Release("agv-9").code(), StatusCode::kNotFound);
}

TEST_F(VehicleStandingStoreTest, AMissingFileIsNotFound) {
  EXPECT_EQ(VehicleStandingStore::Open(dir_.File("missing.db")).status().code(),
            StatusCode::kNotFound);
}

}  // namespace
}  // namespace fleetloc::mosaic_upkeep
