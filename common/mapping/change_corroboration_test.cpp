// Cross-vehicle corroboration of changed floor: a real change seen by two vehicles is confirmed,
// one seen by a single vehicle (however many of its patches) is not, and a forged marking spliced
// into real floor is refuted by the other vehicles' views of that place.
#include "mapping/change_corroboration.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "mapping/forged_patches.h"
#include "mapping/patch_admission.h"

namespace fleetloc::mapping {
namespace {

using testing::ChangedFloorScene;
constexpr double kRes = ChangedFloorScene::kRes;

class ChangeCorroborationTest : public ::testing::Test {
 protected:
  ChangeCorroborationTest() : source_(scene_.old_floor, scene_.geo), admission_(&source_, {}, {}) {}

  // Admits `patch` (it must be) and keeps it as an observed change.
  void Observe(Patch patch, const std::string& vehicle) {
    patch.vehicle_id = vehicle;
    const Admission a = admission_.Evaluate(patch);
    ASSERT_TRUE(a.admitted()) << vehicle << ": " << a.reason;
    ASSERT_FALSE(a.changed_blocks.empty()) << vehicle;
    images_.push_back(patch.image);
    changes_.push_back({nullptr, a.pose, vehicle, a.changed_blocks});
  }
  std::vector<bool> Corroborate(int min_vehicles) {
    for (size_t i = 0; i < changes_.size(); ++i) changes_[i].image = &images_[i];
    CorroborationOptions o;
    o.min_vehicles = min_vehicles;
    return CorroborateChanges(changes_, kRes, o);
  }

  ChangedFloorScene scene_;
  mosaic::ImageRasterSource source_;
  PatchAdmission admission_;
  std::vector<cv::Mat> images_;
  std::vector<ObservedChange> changes_;
};

TEST_F(ChangeCorroborationTest, AChangeSeenByTwoVehiclesIsConfirmed) {
  Observe(scene_.PatchAt({490, 425}, {2 * kRes, -1.5 * kRes, 0.005}), "agv-1");
  Observe(scene_.PatchAt({470, 440}, {-kRes, 2.5 * kRes, -0.003}), "agv-2");
  EXPECT_EQ(Corroborate(2), std::vector<bool>({true, true}));
  EXPECT_EQ(Corroborate(3), std::vector<bool>({false, false}));
  EXPECT_EQ(Corroborate(1), std::vector<bool>({true, true}));
}

TEST_F(ChangeCorroborationTest, OneVehicleDoesNotConfirmItself) {
  Observe(scene_.PatchAt({490, 425}, {}), "agv-1");
  Observe(scene_.PatchAt({470, 440}, {}), "agv-1");
  Observe(scene_.PatchAt({510, 410}, {}), "agv-1");
  EXPECT_EQ(Corroborate(2), std::vector<bool>({false, false, false}));
}

TEST_F(ChangeCorroborationTest, ASplicedMarkingIsRefutedByOtherVehicles) {
  Observe(testing::SplicedPatch(scene_, {490, 425}, "forger"), "forger");
  Observe(scene_.PatchAt({490, 425}, {}), "agv-1");
  Observe(scene_.PatchAt({470, 440}, {}), "agv-2");
  const std::vector<bool> ok = Corroborate(2);
  EXPECT_FALSE(ok[0]);  // the forger's checkerboard: nobody else sees it
  EXPECT_TRUE(ok[1]);
  EXPECT_TRUE(ok[2]);
}

TEST(PatchToPatch, MapsPixelsThroughTheTwoPoses) {
  const geometry::Pose2 a{1.0, 2.0, 0.3};
  const cv::Matx23d same = PatchToPatch({320, 240}, a, {320, 240}, a, kRes);
  EXPECT_NEAR(cv::norm(same - cv::Matx23d(1, 0, 0, 0, 1, 0)), 0.0, 1e-6);
  // b is a moved 10 px "up" its image (+a axis): a's pixel (j, i) is b's (j, i + 10).
  const geometry::Pose2 b = a * geometry::Pose2{10 * kRes, 0.0, 0.0};
  const cv::Matx23d shifted = PatchToPatch({320, 240}, a, {320, 240}, b, kRes);
  EXPECT_NEAR(shifted(0, 2), 0.0, 1e-6);
  EXPECT_NEAR(shifted(1, 2), 10.0, 1e-6);
}

}  // namespace
}  // namespace fleetloc::mapping
