// Patch admission on the server's own evidence, on a real floor photo whose floor changed in a
// known place: true views of the changed floor are admitted at their registered pose whatever
// they claim, forgeries claiming a perfect pose are refused for what they are, and a malformed
// covariance is refused before anything else.
#include "mapping/patch_admission.h"

#include <gtest/gtest.h>

#include <map>

#include "mapping/forged_patches.h"

namespace fleetloc::mapping {
namespace {

using testing::ChangedFloorScene;
constexpr double kRes = ChangedFloorScene::kRes;

class PatchAdmissionTest : public ::testing::Test {
 protected:
  PatchAdmissionTest() : source_(scene_.old_floor, scene_.geo), admission_(&source_, {}, {}) {}

  // A camera-like view: the scene's patch with sensor noise (σ 3 grey levels).
  Patch Noisy(Patch p) {
    cv::Mat noise(p.image.size(), CV_16SC1);
    cv::randn(noise, 0, 3);
    cv::Mat sum;
    cv::add(p.image, noise, sum, cv::noArray(), CV_16S);
    sum.convertTo(p.image, CV_8U);
    return p;
  }

  ChangedFloorScene scene_;
  mosaic::ImageRasterSource source_;
  PatchAdmission admission_;
};

TEST_F(PatchAdmissionTest, TrueViewsOfTheChangedFloorAreAdmittedAtTheirRegisteredPose) {
  const std::vector<std::pair<cv::Point, geometry::Pose2>> views = {
      {{490, 425}, {2.0 * kRes, -1.5 * kRes, 0.3 * M_PI / 180}},
      {{470, 440}, {-1.0 * kRes, 2.5 * kRes, -0.2 * M_PI / 180}},
      {{520, 400}, {0.5 * kRes, 0.5 * kRes, 0.0}}};
  for (const auto& [centre, error] : views) {
    const Admission a = admission_.Evaluate(Noisy(scene_.PatchAt(centre, error)));
    ASSERT_TRUE(a.admitted()) << centre << ": " << a.reason;
    const Eigen::Vector2d truth = scene_.geo.PixelToMap({centre.x * 1.0, centre.y * 1.0});
    EXPECT_LT((Eigen::Vector2d(a.pose.x, a.pose.y) - truth).norm() / kRes, 0.2) << centre;
    // The change covers part of each view: some blocks changed, most still anchor it.
    EXPECT_GT(a.evidence.changed_blocks, 0) << centre;
    EXPECT_LT(a.evidence.changed_fraction(), 0.4) << centre;
    EXPECT_GT(a.evidence.anchor_fraction(), 0.5) << centre;
    EXPECT_NEAR(a.gain, 1.0, 0.1) << centre;
    EXPECT_GT(a.evidence.texture_ratio, 0.5) << centre;
    EXPECT_EQ(a.evidence.flattened_blocks, 0) << centre;
    EXPECT_FALSE(a.changed_blocks.empty());
  }
}

TEST_F(PatchAdmissionTest, APaintedLineIsAPlausibleChange) {
  // A 64 px (3.2 cm) wide line of flat paint across a true view of the old floor: the blocks under
  // it lose their texture, but only a band of them (2 of the 7 block rows).
  Patch painted = scene_.PatchAt({300, 300}, {kRes, -kRes, 0.0});
  painted.image = scene_.old_floor(cv::Rect(140, 180, 320, 240)).clone();
  painted.image(cv::Rect(0, 96, 320, 64)).setTo(cv::Scalar(235));
  const Admission a = admission_.Evaluate(painted);
  ASSERT_TRUE(a.admitted()) << VerdictName(a.verdict) << ": " << a.reason;
  EXPECT_GE(a.evidence.flattened_blocks, 15);
  EXPECT_LE(a.evidence.flattened_fraction(), 0.35);
  EXPECT_NEAR(a.gain, 1.0, 0.1);  // fitted on the blocks that agree, not pulled by the paint
}

TEST_F(PatchAdmissionTest, ForgeriesClaimingAPerfectPoseAreRefused) {
  const std::map<std::string, std::vector<Verdict>> expected = {
      {"garbage", {Verdict::kUnregistered, Verdict::kNoAnchor}},
      {"flat", {Verdict::kUnregistered}},
      {"shifted", {Verdict::kPoseDisagrees}},
      {"shifted_far", {Verdict::kUnregistered, Verdict::kNoAnchor}},
      {"checkerboard", {Verdict::kUnregistered, Verdict::kNoAnchor}},
      {"flattened", {Verdict::kTextureDestroyed, Verdict::kImplausibleChange, Verdict::kNoAnchor}}};
  for (const testing::ForgedPatch& forged : testing::ForgedPatches(scene_, {490, 425})) {
    const Admission a = admission_.Evaluate(forged.patch);
    EXPECT_FALSE(a.admitted()) << forged.kind;
    EXPECT_FALSE(a.reason.empty()) << forged.kind;
    const auto& allowed = expected.at(forged.kind);
    EXPECT_NE(std::find(allowed.begin(), allowed.end(), a.verdict), allowed.end())
        << forged.kind << ": " << VerdictName(a.verdict) << " (" << a.reason << ")";
  }
}

TEST_F(PatchAdmissionTest, TheClaimedCovarianceNeitherAdmitsNorRefuses) {
  // A true view claiming to be perfect is admitted as one claiming 3 px is; its claim only ranks.
  Patch perfect = Noisy(scene_.PatchAt({490, 425}, {1.0 * kRes, -1.0 * kRes, 0.0}));
  perfect.covariance = testing::PerfectCovariance();
  perfect.quality = 1.0;
  Patch modest = scene_.PatchAt({490, 425}, {1.0 * kRes, -1.0 * kRes, 0.0});
  modest.quality = 0.5;
  const Admission a = admission_.Evaluate(perfect), b = admission_.Evaluate(modest);
  ASSERT_TRUE(a.admitted()) << a.reason;
  ASSERT_TRUE(b.admitted()) << b.reason;
  EXPECT_GT(a.rank, b.rank);
  // A huge claimed uncertainty does not widen the search past the server's bound: a view 60 px
  // off is not found, and not admitted.
  Patch vague = scene_.PatchAt({490, 425}, {60 * kRes, 0.0, 0.0});
  vague.covariance =
      Eigen::Vector3d(std::pow(200 * kRes, 2), std::pow(200 * kRes, 2), 0.01).asDiagonal();
  EXPECT_FALSE(admission_.Evaluate(vague).admitted());
}

TEST_F(PatchAdmissionTest, MalformedCovariancesAreRefusedBeforeRegistration) {
  const Patch good = scene_.PatchAt({490, 425}, {});
  Eigen::Matrix3d asymmetric = good.covariance;
  asymmetric(0, 1) = good.covariance(0, 0) / 2;
  Eigen::Matrix3d indefinite = good.covariance;
  indefinite(0, 1) = indefinite(1, 0) = 2 * good.covariance(0, 0);
  for (const Eigen::Matrix3d& bad :
       {Eigen::Matrix3d(Eigen::Matrix3d::Zero()), Eigen::Matrix3d(-good.covariance), asymmetric,
        indefinite, Eigen::Matrix3d(Eigen::Matrix3d::Constant(std::nan("")))}) {
    Patch p = good;
    p.covariance = bad;
    const Admission a = admission_.Evaluate(p);
    EXPECT_EQ(a.verdict, Verdict::kMalformed) << bad;
  }
}

TEST(PatchAdmissionOptions, OutOfRangeOptionsAreNamed) {
  EXPECT_EQ(OptionsProblem(AdmissionOptions{}), "");
  AdmissionOptions o;
  o.max_changed_fraction = 1.0;
  EXPECT_NE(OptionsProblem(o).find("max_changed_fraction"), std::string::npos);
  o = {};
  o.min_search_sigma_px = 30;
  EXPECT_NE(OptionsProblem(o).find("min_search_sigma_px"), std::string::npos);
}

TEST(MeanLocalStdDev, IsZeroOnFlatAndLargeOnACheckerboard) {
  const cv::Mat flat(64, 64, CV_8UC1, cv::Scalar(90));
  EXPECT_NEAR(MeanLocalStdDev(flat, {16, 16, 32, 32}, 7), 0.0, 1e-6);
  const cv::Mat board = testing::Checkerboard({64, 64}, 4);
  EXPECT_GT(MeanLocalStdDev(board, {16, 16, 32, 32}, 7), 80.0);
}

}  // namespace
}  // namespace fleetloc::mapping
