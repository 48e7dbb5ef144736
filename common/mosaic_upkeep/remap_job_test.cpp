// Re-mapping jobs against a stored mosaic: the changed floor reaches the new version's tiles, the
// rest stays byte-identical, patches fold once, and a cancelled job leaves everything as it was.
// A forged vehicle's patches (garbage, flat, shifted, checkerboard, flattened; a perfect claimed
// pose) change no tile in blend or replace mode, are refused with their reasons and quarantine
// the vehicle, while a real change seen by several vehicles is folded.
#include "mosaic_upkeep/remap_job.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "mapping/forged_patches.h"
#include "mosaic/importer.h"
#include "mosaic/test_util.h"

namespace fleetloc::mosaic_upkeep {
using mosaic::ImportImage;
using mosaic::ImportOptions;
using mosaic::MapRect;
using mosaic::MosaicLayout;
using mosaic::OpenMode;
using mosaic::PatchStore;
using mosaic::PutOutcome;
using mosaic::TileKey;
using mosaic::TilesCovering;
using mosaic::TileStore;
namespace {

using Scene = mapping::testing::ChangedFloorScene;
constexpr double kRes = Scene::kRes;

class RemapJobTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::string image = dir_.File("old_floor.png");
    ASSERT_TRUE(cv::imwrite(image, scene_.old_floor));
    path_ = dir_.File("floor.db");
    ImportOptions options;
    options.resolution_m = kRes;
    ASSERT_TRUE(ImportImage(image, options, path_).ok());
    store_ = std::move(TileStore::Open(path_, OpenMode::kReadWrite)).value();
    patches_ = std::move(PatchStore::Open(path_)).value();
    standing_ = std::move(VehicleStandingStore::Open(path_)).value();
  }

  void Put(const std::string& vehicle, const mapping::Patch& p) {
    ASSERT_EQ(*patches_->Put(
                  {vehicle, ++sequence_[vehicle], 1.0, p.pose, p.covariance, p.quality, p.image}),
              PutOutcome::kStored);
  }
  // The two views of the changed floor one vehicle (agv-1) reported, off by a few pixels.
  void PutGenuine() {
    Put("agv-1", scene_.PatchAt({490, 425}, {2 * kRes, -1.5 * kRes, 0.005}));
    Put("agv-1", scene_.PatchAt({470, 440}, {-kRes, 2.5 * kRes, -0.003}));
  }
  // The forger's patches around the change and elsewhere on the floor.
  int PutForged() {
    int n = 0;
    for (cv::Point centre : {cv::Point(490, 425), cv::Point(300, 300), cv::Point(700, 600)}) {
      for (const auto& forged : mapping::testing::ForgedPatches(scene_, centre)) {
        Put("forger", forged.patch);
        ++n;
      }
    }
    return n;
  }

  // The region around the change, in map metres.
  MapRect Region() const {
    const Eigen::Vector2d a = scene_.geo.PixelToMap({400, 500}),
                          b = scene_.geo.PixelToMap({600, 350});
    return {a.x(), a.y(), b.x(), b.y()};
  }
  MapRect Everywhere() const { return {0, 0, 1024 * kRes, 1024 * kRes}; }

  // Every tile's encoded bytes, all levels.
  std::map<TileKey, std::vector<std::uint8_t>> AllTiles() {
    std::map<TileKey, std::vector<std::uint8_t>> tiles;
    const MosaicLayout layout = store_->layout();
    for (int level = 0; level < layout.levels; ++level) {
      TilesCovering(layout, level, {0, 0, layout.width_px >> level, layout.height_px >> level})
          .ForEach([&](const TileKey& k) { tiles[k] = *store_->ReadTileBytes(k); });
    }
    return tiles;
  }
  // Level-0 pixels of `rect` as the store holds them now.
  cv::Mat Pixels(const cv::Rect& rect) {
    cv::Mat out(rect.size(), CV_8UC1);
    TilesCovering(store_->layout(), 0, rect).ForEach([&](const TileKey& k) {
      const cv::Rect tile_rect = TilePixelRect(store_->layout(), k);
      const cv::Rect part = tile_rect & rect;
      (*store_->ReadTile(k))(part - tile_rect.tl()).copyTo(out(part - rect.tl()));
    });
    return out;
  }
  Result<RemapResult> Remap(const MapRect& region, RemapMode mode, const RemapPolicy& policy = {}) {
    return RunRemap(*store_, *patches_, *standing_, {region, mode, policy});
  }

  Scene scene_;
  mosaic::testing::ScratchDir dir_;  // removed with the fixture
  std::string path_;
  std::unique_ptr<TileStore> store_;
  std::unique_ptr<PatchStore> patches_;
  std::unique_ptr<VehicleStandingStore> standing_;
  std::map<std::string, int64_t> sequence_;
};

TEST_F(RemapJobTest, ReplaceCommitsTheChangedFloorAsTheNextVersion) {
  PutGenuine();
  const auto untouched_before = store_->ReadTileBytes({0, 3, 3});
  std::vector<std::string> phases;
  auto result = RunRemap(*store_, *patches_, *standing_, {Region(), RemapMode::kReplace},
                         [&](const RemapProgress& p) { phases.push_back(p.phase); });
  ASSERT_TRUE(result.ok()) << result.status().message();
  EXPECT_EQ(result->new_version, 2);
  EXPECT_EQ(result->patches_folded, 2);
  EXPECT_EQ(result->patches_rejected, 0);
  EXPECT_EQ(result->vehicles.at("agv-1").folded, 2);
  EXPECT_EQ(store_->version(), 2);
  EXPECT_NE(std::find(phases.begin(), phases.end(), "judge"), phases.end());
  EXPECT_NE(std::find(phases.begin(), phases.end(), "commit"), phases.end());
  // Level-0 tile (1, 1) holds most of the change: that part now shows the new floor.
  const cv::Mat tile = *store_->ReadTile({0, 1, 1});
  const cv::Rect part = scene_.change & cv::Rect(256, 256, 256, 256);
  cv::Mat diff;
  cv::absdiff(tile(part - cv::Point(256, 256)), scene_.new_floor(part), diff);
  EXPECT_LT(cv::mean(diff)[0], 3.0);
  EXPECT_EQ(*store_->ReadTileBytes({0, 3, 3}), *untouched_before);  // far away: unchanged
  // Folded once: a second job finds nothing to do.
  auto again = Remap(Region(), RemapMode::kReplace);
  ASSERT_TRUE(again.ok());
  EXPECT_EQ(again->new_version, 2);
  EXPECT_TRUE(again->changed_tiles.empty());
}

// A dry run judges and computes like the job that follows it, and writes nothing: same changed
// tiles and verdicts, the mosaic, the patches' state and the forger's standing untouched.
TEST_F(RemapJobTest, ADryRunPreviewsTheJobAndWritesNothing) {
  PutGenuine();
  const int forged = PutForged();
  const auto tiles_before = AllTiles();
  RemapRequest preview{Everywhere(), RemapMode::kReplace};
  preview.dry_run = true;
  auto dry = RunRemap(*store_, *patches_, *standing_, preview);
  ASSERT_TRUE(dry.ok()) << dry.status().message();
  EXPECT_EQ(dry->new_version, 1);
  EXPECT_FALSE(dry->changed_tiles.empty());
  EXPECT_EQ(dry->patches_folded, 2);
  EXPECT_EQ(dry->vehicles.at("forger").refused, forged);
  EXPECT_EQ(*store_->Refresh(), 1);
  EXPECT_EQ(AllTiles(), tiles_before);
  EXPECT_EQ(patches_->Unfolded(Everywhere(), 1)->patches.size(), static_cast<size_t>(2 + forged));
  EXPECT_FALSE(*standing_->IsQuarantined("forger"));
  EXPECT_TRUE(standing_->All()->empty());
  auto real = Remap(Everywhere(), RemapMode::kReplace);
  ASSERT_TRUE(real.ok()) << real.status().message();
  EXPECT_EQ(real->new_version, 2);
  std::vector<TileKey> previewed = dry->changed_tiles, changed = real->changed_tiles;
  std::sort(previewed.begin(), previewed.end());
  std::sort(changed.begin(), changed.end());
  EXPECT_EQ(previewed, changed);
  EXPECT_EQ(real->patches_folded, dry->patches_folded);
  EXPECT_EQ(RemapSummary(*real), RemapSummary(*dry));
}

class ForgedVehicle : public RemapJobTest, public ::testing::WithParamInterface<RemapMode> {};

TEST_P(ForgedVehicle, ChangesNoMosaicPixelAndIsQuarantined) {
  const int forged = PutForged();
  const auto before = AllTiles();
  auto result = Remap(Everywhere(), GetParam());
  ASSERT_TRUE(result.ok()) << result.status().message();
  EXPECT_EQ(result->new_version, 1);
  EXPECT_EQ(result->patches_folded, 0);
  EXPECT_EQ(result->patches_rejected, forged);
  EXPECT_EQ(AllTiles(), before);  // not one byte of any tile, any level
  const VehicleRemapReport& report = result->vehicles.at("forger");
  EXPECT_EQ(report.refused, forged);
  EXPECT_TRUE(report.quarantined);
  EXPECT_EQ(result->newly_quarantined, std::vector<std::string>{"forger"});
  EXPECT_NE(RemapSummary(*result).find("forger: 0 folded, 18 refused"), std::string::npos)
      << RemapSummary(*result);
  // Refused for good: they are not judged again, and the forger's next patches are refused
  // unjudged.
  EXPECT_EQ(patches_->Counts(1)->refused, forged);
  EXPECT_TRUE(patches_->Unfolded(Everywhere(), 1)->patches.empty());
  EXPECT_TRUE(*standing_->IsQuarantined("forger"));
  Put("forger", scene_.PatchAt({490, 425}, {}));  // even a true view
  auto next = Remap(Everywhere(), GetParam());
  ASSERT_TRUE(next.ok());
  EXPECT_EQ(next->vehicles.at("forger").refused_by.at("quarantined"), 1);
  EXPECT_EQ(AllTiles(), before);
}

INSTANTIATE_TEST_SUITE_P(BlendAndReplace, ForgedVehicle,
                         ::testing::Values(RemapMode::kBlend, RemapMode::kReplace),
                         [](const auto& param_info) {
                           return param_info.param == RemapMode::kBlend ? "Blend" : "Replace";
                         });

TEST_F(RemapJobTest, ARealChangeSeenBySeveralVehiclesIsFoldedBesideAForger) {
  PutForged();
  Put("agv-1", scene_.PatchAt({490, 425}, {2 * kRes, -1.5 * kRes, 0.005}));
  Put("agv-2", scene_.PatchAt({470, 440}, {-kRes, 2.5 * kRes, -0.003}));
  Put("agv-3", scene_.PatchAt({510, 415}, {0.5 * kRes, kRes, 0.002}));
  Put("agv-3",
      mapping::testing::SplicedPatch(scene_, {700, 600}, "agv-3"));  // agv-3 is compromised too
  RemapPolicy policy;
  policy.corroboration.min_vehicles = 2;
  auto result = Remap(Everywhere(), RemapMode::kReplace, policy);
  ASSERT_TRUE(result.ok()) << result.status().message();
  EXPECT_EQ(result->new_version, 2);
  EXPECT_EQ(result->vehicles.at("agv-1").folded, 1);
  EXPECT_EQ(result->vehicles.at("agv-2").folded, 1);
  EXPECT_EQ(result->vehicles.at("agv-3").folded, 1);
  EXPECT_EQ(result->vehicles.at("agv-3").held, 1);  // the spliced marking nobody else saw
  EXPECT_EQ(result->vehicles.at("forger").folded, 0);
  // The changed area now shows the changed reality; the spliced checkerboard is not there.
  cv::Mat diff;
  cv::absdiff(Pixels(scene_.change), scene_.new_floor(scene_.change), diff);
  EXPECT_LT(cv::mean(diff)[0], 3.0);
  const cv::Rect spliced(700 - 160 + 112, 600 - 120 + 72, 96, 96);
  cv::absdiff(Pixels(spliced), scene_.old_floor(spliced), diff);
  EXPECT_EQ(cv::countNonZero(diff), 0);
}

TEST_F(RemapJobTest, AReleasedVehicleIsJudgedAgain) {
  PutForged();
  ASSERT_TRUE(Remap(Everywhere(), RemapMode::kBlend).ok());
  ASSERT_TRUE(*standing_->IsQuarantined("forger"));
  ASSERT_TRUE(standing_->Release("forger").ok());
  EXPECT_FALSE(*standing_->IsQuarantined("forger"));
  Put("forger", scene_.PatchAt({490, 425}, {}));  // a true view this time
  auto result = Remap(Region(), RemapMode::kReplace);
  ASSERT_TRUE(result.ok());
  EXPECT_EQ(result->vehicles.at("forger").folded, 1);
  EXPECT_EQ(result->new_version, 2);
  EXPECT_EQ(standing_->Release("nobody").code(), StatusCode::kNotFound);
}

TEST_F(RemapJobTest, CancelledJobLeavesTheMosaicAndThePatchesAsTheyWere) {
  PutGenuine();
  const auto before = store_->ReadTileBytes({0, 1, 1});
  std::atomic<bool> cancel{true};
  auto result =
      RunRemap(*store_, *patches_, *standing_, {Region(), RemapMode::kBlend}, {}, &cancel);
  ASSERT_FALSE(result.ok());
  auto reopened = TileStore::Open(path_, OpenMode::kReadOnly);
  EXPECT_EQ((*reopened)->version(), 1);
  EXPECT_EQ(*(*reopened)->ReadTileBytes({0, 1, 1}), *before);
  EXPECT_EQ(patches_->Unfolded(Region(), 1)->patches.size(), 2u);
  auto rerun = Remap(Region(), RemapMode::kBlend);
  ASSERT_TRUE(rerun.ok()) << rerun.status().message();
  EXPECT_EQ(rerun->new_version, 2);
}

TEST_F(RemapJobTest, BadRegionsAndPoliciesAreRejected) {
  const MapRect inverted{0.3, 0.3, 0.2, 0.2}, empty{0.2, 0.2, 0.2, 0.3}, outside{5, 5, 6, 6};
  const MapRect nan{std::nan(""), 0, 1, 1};
  for (const MapRect& r : {inverted, empty, outside, nan}) {
    auto result = Remap(r, RemapMode::kBlend);
    ASSERT_FALSE(result.ok());
    EXPECT_EQ(result.status().code(), StatusCode::kInvalidInput) << result.status().message();
  }
  RemapPolicy bad;
  bad.admission.max_changed_fraction = 2;
  auto result = Remap(Region(), RemapMode::kBlend, bad);
  ASSERT_FALSE(result.ok());
  EXPECT_NE(result.status().message().find("max_changed_fraction"), std::string::npos);
  EXPECT_EQ(store_->version(), 1);
}

}  // namespace
}  // namespace fleetloc::mosaic_upkeep
