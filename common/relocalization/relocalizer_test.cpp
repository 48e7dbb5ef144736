// Relocalizer on a real floor photo: sim-rendered frames (noise, dust, lighting, blur, grain) at
// random poses and headings are relocalized against the truth; bad frames give clear errors; on
// the photo twice side by side the features never give a wrong pose (ambiguous inside a copy);
// a place the self-similarity report names is refused.
// Under dust on polished concrete the fine dense search finds what the dense search cannot, and
// never a frame of another floor.
// Multi-frame relocalization with odometry: a drive whose single frames are all refused is found
// from the frames combined; on a floor that repeats itself it stays ambiguous; travel beyond the
// bound starts a new trajectory.
#include "relocalization/relocalizer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <random>

#include "relocalization/test_floors.h"
#include "sim/camera_renderer.h"
#include "sim/random_pose.h"
#include "sim/run_simulator.h"
#include "sim/stress_camera.h"

namespace fleetloc::relocalization {
namespace {

constexpr double kResolutionM = 0.0005;

struct Scene {
  mosaic::ImageRasterSource floor;
  geometry::CameraModel camera;
};

Scene MossScene() {
  const cv::Mat photo = cv::imread(FLEETLOC_SOURCE_DIR "/deploy/demo/floors/moss_2560x1600.jpg",
                                   cv::IMREAD_GRAYSCALE);
  EXPECT_FALSE(photo.empty());
  geometry::CameraModel camera;  // 640×480 at 0.5 mm/px, mounted 0.40 m ahead
  camera.mount = {0.40, 0.0, 0.0};
  return {mosaic::ImageRasterSource(photo, {0.0, photo.rows * kResolutionM, kResolutionM}), camera};
}

// A found pose within 2 mm and 0.5° of the truth.
void ExpectNearTruth(const geometry::Pose2& pose, const geometry::Pose2& truth, int trial) {
  EXPECT_LT(std::hypot(pose.x - truth.x, pose.y - truth.y), 0.002) << "trial " << trial;
  EXPECT_LT(std::abs(geometry::WrapAngle(pose.theta - truth.theta)), 0.5 * M_PI / 180)
      << "trial " << trial;
}

TEST(Relocalizer, FindsRandomPosesAndHeadingsOnARealFloorWithinTwoMillimetres) {
  Scene scene = MossScene();
  const Result<PlaceIndex> index = PlaceIndex::Build(scene.floor, PlaceIndexOptions{});
  ASSERT_TRUE(index.ok()) << index.status().message();
  auto relocalizer = Relocalizer::Create(&*index, &scene.floor, scene.camera, RelocalizerOptions{});
  ASSERT_TRUE(relocalizer.ok()) << relocalizer.status().message();
  sim::CameraRenderer renderer(&scene.floor, scene.camera, sim::RenderOptions{}, 11);
  std::mt19937_64 rng(5);
  const int kTrials = 24;
  int correct = 0, wrong = 0;
  for (int trial = 0; trial < kTrials; ++trial) {
    const geometry::Pose2 truth = sim::RandomFullFramePose(scene.floor.layout(), scene.camera, rng);
    const cv::Mat frame = renderer.Render(truth, {0, 0}, trial).image;
    const Result<Relocalization> found = (*relocalizer)->Relocalize(frame);
    ASSERT_TRUE(found.ok()) << found.status().message();
    if (!found->found) continue;
    const geometry::Pose2 pose = found->base_in_map.pose;
    const double error_m = std::hypot(pose.x - truth.x, pose.y - truth.y);
    const double error_rad = std::abs(geometry::WrapAngle(pose.theta - truth.theta));
    if (error_m < 0.002 && error_rad < 0.5 * M_PI / 180) {
      ++correct;
    } else {
      ++wrong;
    }
  }
  // Measured: 24 of 24 within 0.06 mm and 0.01°.
  EXPECT_GE(correct, kTrials - 1);
  EXPECT_EQ(wrong, 0);
}

TEST(Relocalizer, EmptyOrWrongFramesAreClearErrors) {
  Scene scene = MossScene();
  const Result<PlaceIndex> index = PlaceIndex::Build(scene.floor, PlaceIndexOptions{});
  ASSERT_TRUE(index.ok());
  auto relocalizer = Relocalizer::Create(&*index, &scene.floor, scene.camera, RelocalizerOptions{});
  ASSERT_TRUE(relocalizer.ok());
  const Result<Relocalization> empty = (*relocalizer)->Relocalize(cv::Mat());
  ASSERT_FALSE(empty.ok());
  EXPECT_NE(empty.status().message().find("empty"), std::string::npos);
  const Result<Relocalization> small = (*relocalizer)->Relocalize(cv::Mat(240, 320, CV_8UC1));
  ASSERT_FALSE(small.ok());
  EXPECT_NE(small.status().message().find("320x240"), std::string::npos);
  const Result<Relocalization> colour = (*relocalizer)->Relocalize(cv::Mat(480, 640, CV_8UC3));
  EXPECT_FALSE(colour.ok());
}

TEST(Relocalizer, BlankFrameIsNotFoundWithAReason) {
  Scene scene = MossScene();
  const Result<PlaceIndex> index = PlaceIndex::Build(scene.floor, PlaceIndexOptions{});
  ASSERT_TRUE(index.ok());
  auto relocalizer = Relocalizer::Create(&*index, &scene.floor, scene.camera, RelocalizerOptions{});
  ASSERT_TRUE(relocalizer.ok());
  const Result<Relocalization> blank =
      (*relocalizer)->Relocalize(cv::Mat(480, 640, CV_8UC1, cv::Scalar(128)));
  ASSERT_TRUE(blank.ok());
  EXPECT_FALSE(blank->found);
  EXPECT_NE(blank->reason.find("no consistent pose votes"), std::string::npos) << blank->reason;
}

TEST(Relocalizer, BadOptionsAndMismatchedCameraAreRejected) {
  Scene scene = MossScene();
  const Result<PlaceIndex> index = PlaceIndex::Build(scene.floor, PlaceIndexOptions{});
  ASSERT_TRUE(index.ok());
  RelocalizerOptions options;
  options.clustering.radius_m = -1;
  EXPECT_FALSE(Relocalizer::Create(&*index, &scene.floor, scene.camera, options).ok());
  options = RelocalizerOptions{};
  options.dense_attempt_budget_ms = std::nan("");
  const auto no_budget = Relocalizer::Create(&*index, &scene.floor, scene.camera, options);
  ASSERT_FALSE(no_budget.ok());
  EXPECT_NE(no_budget.status().message().find("dense_attempt_budget_ms"), std::string::npos);
  options = RelocalizerOptions{};
  options.dense_fine_refine_sweep_finest_stride = 0;
  EXPECT_FALSE(Relocalizer::Create(&*index, &scene.floor, scene.camera, options).ok());
  options = RelocalizerOptions{};
  options.twin_contrast_max_ratio = 1.0;  // a rival as good as the best would be told apart
  const auto no_contrast = Relocalizer::Create(&*index, &scene.floor, scene.camera, options);
  ASSERT_FALSE(no_contrast.ok());
  EXPECT_NE(no_contrast.status().message().find("twin_contrast_max_ratio"), std::string::npos);
  geometry::CameraModel coarse = scene.camera;
  coarse.resolution_m = 0.001;
  const auto mismatched = Relocalizer::Create(&*index, &scene.floor, coarse, RelocalizerOptions{});
  ASSERT_FALSE(mismatched.ok());
  EXPECT_NE(mismatched.status().message().find("resolution"), std::string::npos);
}

// Poses found on a floor that repeats itself, against the truth: a strip of the photo, a part of
// it twice, another strip (the twin of a frame across the copies' border is then wholly on the
// floor, and differs). Frames wholly inside one copy have two true answers and must be refused as
// ambiguous; frames across the border have one, and a pose found there must be it.
TEST(Relocalizer, TheFeaturesOnAFloorThatRepeatsItselfAreAmbiguousNeverAWrongPose) {
  Scene scene = MossScene();
  const cv::Mat photo = scene.floor.ReadBlock(0, cv::Rect(0, 0, 1800, 1600));
  const cv::Mat copy = photo(cv::Rect(0, 0, 1000, 1600));
  cv::Mat floor_image;
  cv::hconcat(std::vector<cv::Mat>{photo(cv::Rect(1000, 0, 400, 1600)), copy, copy,
                                   photo(cv::Rect(1400, 0, 400, 1600))},
              floor_image);
  mosaic::ImageRasterSource floor(floor_image,
                                  {0.0, floor_image.rows * kResolutionM, kResolutionM});
  const Result<PlaceIndex> index = PlaceIndex::Build(floor, PlaceIndexOptions{});
  ASSERT_TRUE(index.ok()) << index.status().message();
  auto relocalizer = Relocalizer::Create(&*index, &floor, scene.camera, RelocalizerOptions{});
  ASSERT_TRUE(relocalizer.ok()) << relocalizer.status().message();
  sim::CameraRenderer renderer(&floor, scene.camera, sim::RenderOptions{}, 25);
  const double border_m = 1400 * kResolutionM;  // between the copies, 0.5 m wide each
  int across_found = 0;
  for (int trial = 0; trial < 8; ++trial) {
    // Even trials: the camera (frame centre) inside the left copy; odd: on the border.
    const double x = trial % 2 == 0 ? 0.41 + 0.01 * trial : border_m - 0.04 + 0.01 * trial;
    const geometry::Pose2 camera_pose{x, 0.2 + 0.025 * trial, 0.8 * trial - 3.0};
    const geometry::Pose2 truth = camera_pose * scene.camera.mount.Inverse();
    const Result<Relocalization> r =
        (*relocalizer)->Relocalize(renderer.Render(truth, {0, 0}, trial).image);
    ASSERT_TRUE(r.ok()) << r.status().message();
    if (trial % 2 == 0) {
      EXPECT_FALSE(r->found) << "trial " << trial << " found " << r->base_in_map.pose.x;
      EXPECT_TRUE(r->ambiguous) << r->reason;
      continue;
    }
    if (!r->found) continue;
    ++across_found;
    ExpectNearTruth(r->base_in_map.pose, truth, trial);
  }
  EXPECT_GE(across_found, 3);
}

// A plain-concrete photograph (data/stress_floors) with a 320×240 camera: too few features.
struct PlainScene {
  cv::Mat photo;
  geometry::CameraModel camera;
};

PlainScene PlainConcreteScene(const std::string& photo = "plain_concrete_g4.jpg") {
  PlainScene scene;
  scene.photo =
      cv::imread(FLEETLOC_SOURCE_DIR "/data/stress_floors/" + photo, cv::IMREAD_GRAYSCALE);
  EXPECT_FALSE(scene.photo.empty());
  scene.camera.width_px = 320;
  scene.camera.height_px = 240;
  scene.camera.cx_px = 160;
  scene.camera.cy_px = 120;
  scene.camera.mount = {0.40, 0.0, 0.0};
  return scene;
}

TEST(Relocalizer, WithoutAnIndexTheDenseSearchFindsPosesOnPlainConcrete) {
  PlainScene scene = PlainConcreteScene();
  mosaic::ImageRasterSource floor(scene.photo,
                                  {0.0, scene.photo.rows * kResolutionM, kResolutionM});
  auto relocalizer = Relocalizer::Create(nullptr, &floor, scene.camera, RelocalizerOptions{});
  ASSERT_TRUE(relocalizer.ok()) << relocalizer.status().message();
  sim::CameraRenderer renderer(&floor, scene.camera, sim::RenderOptions{}, 21);
  std::mt19937_64 rng(9);
  int correct = 0;
  for (int trial = 0; trial < 6; ++trial) {
    const geometry::Pose2 truth = sim::RandomFullFramePose(floor.layout(), scene.camera, rng);
    const Result<Relocalization> r =
        (*relocalizer)->Relocalize(renderer.Render(truth, {0, 0}, trial).image);
    ASSERT_TRUE(r.ok()) << r.status().message();
    if (!r->found) continue;
    ExpectNearTruth(r->base_in_map.pose, truth, trial);
    ++correct;
  }
  EXPECT_GE(correct, 5);
}

// The tuning polished concrete (grey std 5.7) under dust: the dense search sees only the dust
// (0 of 30 trials in the stress bench before the fine search); one level finer the floor shows.
TEST(Relocalizer, TheFineDenseSearchFindsPosesOnDustyPolishedConcrete) {
  PlainScene scene = PlainConcreteScene("polished_concrete_024.png");
  mosaic::ImageRasterSource floor(scene.photo,
                                  {0.0, scene.photo.rows * kResolutionM, kResolutionM});
  RelocalizerOptions coarse_only;
  coarse_only.dense_fine_search = false;
  auto before = Relocalizer::Create(nullptr, &floor, scene.camera, coarse_only);
  auto after = Relocalizer::Create(nullptr, &floor, scene.camera, RelocalizerOptions{});
  ASSERT_TRUE(before.ok() && after.ok());
  sim::CameraRenderer renderer(&floor, scene.camera, *sim::StressCameraEffects("dusty"), 31);
  std::mt19937_64 rng(17);
  int found_before = 0, correct = 0;
  for (int trial = 0; trial < 4; ++trial) {
    const geometry::Pose2 truth = sim::RandomFullFramePose(floor.layout(), scene.camera, rng);
    const cv::Mat frame = renderer.Render(truth, {0, 0}, trial).image;
    const Result<Relocalization> coarse = (*before)->Relocalize(frame);
    ASSERT_TRUE(coarse.ok());
    EXPECT_FALSE(coarse->dense_fine);
    found_before += coarse->found;
    const Result<Relocalization> r = (*after)->Relocalize(frame);
    ASSERT_TRUE(r.ok());
    EXPECT_TRUE(r->dense_fine) << "trial " << trial;
    if (!r->found) continue;
    ExpectNearTruth(r->base_in_map.pose, truth, trial);
    EXPECT_LE(r->dense_fine_second, 0.6 * r->dense_fine_best);
    ++correct;
  }
  EXPECT_EQ(found_before, 0);
  EXPECT_GE(correct, 3);
}

// A frame of another floor (worn asphalt) under dust against the polished concrete's mosaic: the
// fine search runs and its best is a chance peak (0.042–0.050 measured, the gate 0.09), never a
// pose; nor is the best of its refine level's own sweep, which runs when the attempt's budget
// allows it, and is named in the reason when it does not.
TEST(Relocalizer, AFrameOfAnotherFloorIsNeverFoundByTheFineSearch) {
  PlainScene scene = PlainConcreteScene("polished_concrete_024.png");
  PlainScene other = PlainConcreteScene("worn_asphalt_b1.jpg");
  mosaic::ImageRasterSource floor(scene.photo,
                                  {0.0, scene.photo.rows * kResolutionM, kResolutionM});
  mosaic::ImageRasterSource elsewhere(other.photo,
                                      {0.0, other.photo.rows * kResolutionM, kResolutionM});
  RelocalizerOptions always, never;
  always.dense_attempt_budget_ms = 1e9;
  never.dense_attempt_budget_ms = 0;
  auto swept = Relocalizer::Create(nullptr, &floor, scene.camera, always);
  auto unswept = Relocalizer::Create(nullptr, &floor, scene.camera, never);
  ASSERT_TRUE(swept.ok() && unswept.ok());
  sim::CameraRenderer renderer(&elsewhere, scene.camera, *sim::StressCameraEffects("dusty"), 46);
  std::mt19937_64 rng(46);
  for (int trial = 0; trial < 3; ++trial) {
    const geometry::Pose2 pose = sim::RandomFullFramePose(elsewhere.layout(), scene.camera, rng);
    const cv::Mat frame = renderer.Render(pose, {0, 0}, trial).image;
    const Result<Relocalization> r = (*swept)->Relocalize(frame);
    ASSERT_TRUE(r.ok());
    EXPECT_FALSE(r->found) << "trial " << trial << ": " << r->reason;
    EXPECT_TRUE(r->dense_fine) << "trial " << trial;
    EXPECT_TRUE(r->dense_fine_refine_sweep) << "trial " << trial << ": " << r->reason;
    EXPECT_EQ(r->dense_fine_refine_sweep_stride, always.dense_fine_refine_sweep_finest_stride);
    const Result<Relocalization> u = (*unswept)->Relocalize(frame);
    ASSERT_TRUE(u.ok());
    EXPECT_FALSE(u->found);
    EXPECT_FALSE(u->dense_fine_refine_sweep);
    EXPECT_EQ(u->dense_fine_refine_sweep_stride, 0);
    EXPECT_GT(u->dense_fine_refine_sweep_predicted_ms, 0.0);
    EXPECT_NE(u->reason.find("no refine-level sweep"), std::string::npos) << u->reason;
  }
}

// The same floor as the stress bench gives a 1280×1024 camera (the photograph ×4, bicubic),
// under dust: the fine search sweeps at 8 mm/px, where the floor's detail is gone, and its best
// is a chance peak; its refine level swept itself (4 mm/px) finds the truth.
TEST(Relocalizer, TheRefineLevelSweepFindsWhatTheFineSweepMissesAt1280x1024) {
  PlainScene scene = PlainConcreteScene("polished_concrete_024.png");
  cv::Mat photo;
  cv::resize(scene.photo, photo, {}, 4, 4, cv::INTER_CUBIC);
  mosaic::ImageRasterSource floor(photo, {0.0, photo.rows * kResolutionM, kResolutionM});
  const geometry::CameraModel camera = sim::DefaultSimCameraModel(1280, 1024, kResolutionM);
  RelocalizerOptions without;
  without.dense_fine_refine_sweep = false;
  RelocalizerOptions with;
  with.dense_attempt_budget_ms = 1e9;  // the budget is the vehicle's; this test measures the sweep
  auto before = Relocalizer::Create(nullptr, &floor, camera, without);
  auto after = Relocalizer::Create(nullptr, &floor, camera, with);
  ASSERT_TRUE(before.ok() && after.ok());
  sim::CameraRenderer renderer(&floor, camera, *sim::StressCameraEffects("dusty"), 48);
  std::mt19937_64 rng(48);
  int found_before = 0, swept = 0, correct = 0;
  for (int trial = 0; trial < 4; ++trial) {
    const geometry::Pose2 truth = sim::RandomFullFramePose(floor.layout(), camera, rng);
    const cv::Mat frame = renderer.Render(truth, {0, 0}, trial).image;
    const Result<Relocalization> fine = (*before)->Relocalize(frame);
    const Result<Relocalization> r = (*after)->Relocalize(frame);
    ASSERT_TRUE(fine.ok() && r.ok());
    found_before += fine->found;
    swept += r->dense_fine_refine_sweep;
    if (!r->found) continue;
    ExpectNearTruth(r->base_in_map.pose, truth, trial);
    ++correct;
  }
  // Measured: the fine search alone found 1 of 4; with the sweep 4 of 4, 3 of them from the sweep
  // (bests 0.14–0.17, seconds 0.069–0.071).
  EXPECT_GE(swept, 2);
  EXPECT_GE(correct, found_before + 2);
}

TEST(Relocalizer, APoseInAPlaceTheSelfSimilarityReportNamesIsRefused) {
  PlainScene scene = PlainConcreteScene();
  mosaic::ImageRasterSource floor(scene.photo,
                                  {0.0, scene.photo.rows * kResolutionM, kResolutionM});
  auto relocalizer = Relocalizer::Create(nullptr, &floor, scene.camera, RelocalizerOptions{});
  ASSERT_TRUE(relocalizer.ok()) << relocalizer.status().message();
  sim::CameraRenderer renderer(&floor, scene.camera, sim::RenderOptions{}, 26);
  const geometry::Pose2 camera_pose{0.25, 0.26, 0.4};
  const cv::Mat frame =
      renderer.Render(camera_pose * scene.camera.mount.Inverse(), {0, 0}, 0).image;
  const Result<Relocalization> alone = (*relocalizer)->Relocalize(frame);
  ASSERT_TRUE(alone.ok());
  ASSERT_TRUE(alone->found) << alone->reason;
  // Named as a twin 30 mm from the camera (within half the frame's 120 mm short side): refused.
  const geometry::Pose2 elsewhere{0.1, 0.1, 0.0};
  (*relocalizer)->SetTwinPlaces({{elsewhere, camera_pose * geometry::Pose2{0.03, 0.0, 0.0}}});
  const Result<Relocalization> named = (*relocalizer)->Relocalize(frame);
  ASSERT_TRUE(named.ok());
  EXPECT_FALSE(named->found);
  EXPECT_TRUE(named->ambiguous);
  EXPECT_NE(named->reason.find("self-similarity report"), std::string::npos) << named->reason;
  // Named 100 mm away: found again.
  (*relocalizer)->SetTwinPlaces({{elsewhere, camera_pose * geometry::Pose2{0.1, 0.0, 0.0}}});
  const Result<Relocalization> apart = (*relocalizer)->Relocalize(frame);
  ASSERT_TRUE(apart.ok());
  EXPECT_TRUE(apart->found) << apart->reason;
}

TEST(Relocalizer, AFloorThatRepeatsItselfIsAmbiguousNeverAWrongPose) {
  PlainScene scene = PlainConcreteScene();
  cv::Mat twice;
  cv::hconcat(scene.photo, scene.photo, twice);
  mosaic::ImageRasterSource floor(twice, {0.0, twice.rows * kResolutionM, kResolutionM});
  auto relocalizer = Relocalizer::Create(nullptr, &floor, scene.camera, RelocalizerOptions{});
  ASSERT_TRUE(relocalizer.ok()) << relocalizer.status().message();
  sim::CameraRenderer renderer(&floor, scene.camera, sim::RenderOptions{}, 22);
  for (int trial = 0; trial < 4; ++trial) {  // frames wholly inside the left copy
    const geometry::Pose2 camera_pose{0.15 + 0.05 * trial, 0.2 + 0.04 * trial, 0.9 * trial - 1.2};
    const geometry::Pose2 truth = camera_pose * scene.camera.mount.Inverse();
    const Result<Relocalization> r =
        (*relocalizer)->Relocalize(renderer.Render(truth, {0, 0}, trial).image);
    ASSERT_TRUE(r.ok());
    EXPECT_FALSE(r->found) << "trial " << trial;
    EXPECT_NE(r->reason.find("ambiguous"), std::string::npos) << r->reason;
  }
}

// Plain concrete g4 with its cloned patch (test_floors.h) as the floor, and the 320×240 camera.
struct ClonedFloor {
  PlainScene scene = PlainConcreteScene();
  testing::ClonedPatch cloned = testing::WithClonedPatch(scene.photo);
  int rows = cloned.photo.rows;
  mosaic::ImageRasterSource floor{cloned.photo, testing::GeoOf(cloned.photo)};
};

// A floor photograph with a cloned patch (test_floors.h): a frame two thirds over the patch is
// found, told from the copy by the third off it, and refused as ambiguous without that contrast;
// a frame wholly inside the patch is ambiguous either way. Measured: the found place correlates
// 0.67–0.75 where the views differ (23–45 % of the frame), the copy −0.02–0.07 there.
TEST(Relocalizer, AFramePartlyOverAClonedPatchIsToldFromItsCopy) {
  ClonedFloor c;
  const PlainScene& scene = c.scene;
  const int rows = c.rows;
  mosaic::ImageRasterSource& floor = c.floor;
  RelocalizerOptions without;
  without.twin_contrast = false;
  auto relocalizer = Relocalizer::Create(nullptr, &floor, scene.camera, RelocalizerOptions{});
  auto refusing = Relocalizer::Create(nullptr, &floor, scene.camera, without);
  ASSERT_TRUE(relocalizer.ok() && refusing.ok());
  sim::CameraRenderer renderer(&floor, scene.camera, sim::RenderOptions{}, 23);
  constexpr int kFrom = testing::ClonedPatch::kFromPx, kSide = testing::ClonedPatch::kSidePx;
  struct Place {
    double u, v, theta;
  };
  // Two thirds over the patch, across its left, top, right and bottom sides.
  const Place partly[] = {{kFrom + 50, kFrom + 200, 0.0},
                          {kFrom + 180, kFrom + 40, 1.4},
                          {kFrom + kSide - 50, kFrom + 150, 3.0},
                          {kFrom + 230, kFrom + kSide - 40, -1.7}};
  for (int trial = 0; trial < 4; ++trial) {
    const Place& p = partly[trial];
    const geometry::Pose2 truth = testing::CameraCentredAt(scene.camera, p.u, p.v, rows, p.theta) *
                                  scene.camera.mount.Inverse();
    const cv::Mat frame = renderer.Render(truth, {0, 0}, trial).image;
    const Result<Relocalization> r = (*relocalizer)->Relocalize(frame);
    ASSERT_TRUE(r.ok());
    ASSERT_TRUE(r->found) << "trial " << trial << ": " << r->reason;
    ExpectNearTruth(r->base_in_map.pose, truth, trial);
    EXPECT_GE(r->twins_told_apart, 1) << "trial " << trial;
    const Result<Relocalization> refused = (*refusing)->Relocalize(frame);
    ASSERT_TRUE(refused.ok());
    EXPECT_FALSE(refused->found) << "trial " << trial;
    EXPECT_TRUE(refused->ambiguous) << "trial " << trial << ": " << refused->reason;
  }
  const geometry::Pose2 inside =
      testing::CameraCentredAt(scene.camera, kFrom + 200, kFrom + 200, rows, 0.4) *
      scene.camera.mount.Inverse();
  const Result<Relocalization> r =
      (*relocalizer)->Relocalize(renderer.Render(inside, {0, 0}, 9).image);
  ASSERT_TRUE(r.ok());
  EXPECT_FALSE(r->found);
  EXPECT_TRUE(r->ambiguous) << r->reason;
}

// The same floor, but what tells a frame's place from the patch's copy is hidden: the frames are
// taken where the floor around the patch (or around its copy) is covered by a plain grey sheet,
// so only the copied part shows. Nothing can tell the two apart: never a pose, and no wrong one.
TEST(Relocalizer, AFrameWhoseDifferenceFromTheCopyIsCoveredIsRefused) {
  ClonedFloor c;
  const PlainScene& scene = c.scene;
  const testing::ClonedPatch& cloned = c.cloned;
  const int rows = c.rows;
  mosaic::ImageRasterSource& floor = c.floor;
  auto relocalizer = Relocalizer::Create(nullptr, &floor, scene.camera, RelocalizerOptions{});
  ASSERT_TRUE(relocalizer.ok());
  constexpr int kSide = testing::ClonedPatch::kSidePx;
  for (const int corner : {testing::ClonedPatch::kFromPx, testing::ClonedPatch::kToPx}) {
    cv::Mat covered(cloned.photo.size(), CV_8UC1, cv::Scalar(128));
    const cv::Rect patch(corner, corner, kSide, kSide);
    cloned.photo(patch).copyTo(covered(patch));
    mosaic::ImageRasterSource seen(covered, testing::GeoOf(covered));
    sim::CameraRenderer renderer(&seen, scene.camera, sim::RenderOptions{}, 24);
    const geometry::Pose2 truth =
        testing::CameraCentredAt(scene.camera, corner + 50, corner + 200, rows, 0.0) *
        scene.camera.mount.Inverse();
    const Result<Relocalization> r =
        (*relocalizer)->Relocalize(renderer.Render(truth, {0, 0}, 1).image);
    ASSERT_TRUE(r.ok());
    EXPECT_FALSE(r->found) << "patch at " << corner << ": " << r->reason;
    EXPECT_TRUE(r->ambiguous) << "patch at " << corner << ": " << r->reason;
    EXPECT_EQ(r->twins_told_apart, 0) << r->reason;
    // The contrast ran over the covered third and found nothing of either place there.
    EXPECT_GT(r->twin_contrast.share, 0.15);
    EXPECT_LT(std::abs(r->twin_contrast.own), 0.1);
  }
}

// Base poses of a 3-frame drive (40 mm steps, turning 0.05 rad a step) inside the left 0.3 m of
// the floor, with odometry 2 % long.
struct Drive {
  std::vector<geometry::Pose2> truth, odometry;
};

Drive ShortDrive(const geometry::CameraModel& camera, const geometry::Pose2& first_camera) {
  Drive d;
  for (int k = 0; k < 3; ++k) {
    const geometry::Pose2 cam = first_camera * geometry::Pose2{0.04 * k, 0.0, 0.05 * k};
    d.truth.push_back(cam * camera.mount.Inverse());
    const geometry::Pose2 moved = d.truth[0].Inverse() * d.truth.back();
    d.odometry.push_back({1.02 * moved.x, 1.02 * moved.y, moved.theta});
  }
  return d;
}

TEST(Relocalizer, MultiFrameFindsTheNewestPoseWhenEverySingleFrameIsRefused) {
  PlainScene scene = PlainConcreteScene();
  mosaic::ImageRasterSource floor(scene.photo,
                                  {0.0, scene.photo.rows * kResolutionM, kResolutionM});
  RelocalizerOptions options;
  options.dense_min_correlation = 0.99;  // no single frame passes
  options.dense_fine_search = false;
  options.trajectory_frames = 3;
  auto relocalizer = Relocalizer::Create(nullptr, &floor, scene.camera, options);
  ASSERT_TRUE(relocalizer.ok()) << relocalizer.status().message();
  sim::CameraRenderer renderer(&floor, scene.camera, sim::RenderOptions{}, 23);
  const Drive drive = ShortDrive(scene.camera, {0.12, 0.2, 0.7});
  Result<Relocalization> r =
      (*relocalizer)
          ->Relocalize(renderer.Render(drive.truth[0], {0, 0}, 0).image, drive.odometry[0]);
  ASSERT_TRUE(r.ok());
  EXPECT_FALSE(r->found);
  EXPECT_EQ(r->trajectory_frames, 1);
  r = (*relocalizer)
          ->Relocalize(renderer.Render(drive.truth[1], {0, 0}, 1).image, drive.odometry[1]);
  ASSERT_TRUE(r.ok());
  ASSERT_TRUE(r->found) << r->reason;
  EXPECT_TRUE(r->from_trajectory);
  EXPECT_EQ(r->trajectory_frames, 2);
  const geometry::Pose2 pose = r->base_in_map.pose;
  EXPECT_LT(std::hypot(pose.x - drive.truth[1].x, pose.y - drive.truth[1].y), 0.002);
  EXPECT_LT(std::abs(geometry::WrapAngle(pose.theta - drive.truth[1].theta)), 0.5 * M_PI / 180);
  // Measured: 0.01 mm off; the two frames' mean 0.66, the best distinct alternative 0.12.
  EXPECT_LT(r->trajectory_second, 0.3 * r->trajectory_best);
}

TEST(Relocalizer, MultiFrameOnAFloorThatRepeatsItselfIsAmbiguousAndTravelStartsAgain) {
  PlainScene scene = PlainConcreteScene();
  cv::Mat twice;
  cv::hconcat(scene.photo, scene.photo, twice);
  mosaic::ImageRasterSource floor(twice, {0.0, twice.rows * kResolutionM, kResolutionM});
  RelocalizerOptions options;
  options.trajectory_frames = 3;
  auto relocalizer = Relocalizer::Create(nullptr, &floor, scene.camera, options);
  ASSERT_TRUE(relocalizer.ok()) << relocalizer.status().message();
  sim::CameraRenderer renderer(&floor, scene.camera, sim::RenderOptions{}, 24);
  const Drive drive = ShortDrive(scene.camera, {0.12, 0.2, 0.7});
  for (int k = 0; k < 3; ++k) {
    const Result<Relocalization> r =
        (*relocalizer)
            ->Relocalize(renderer.Render(drive.truth[k], {0, 0}, k).image, drive.odometry[k]);
    ASSERT_TRUE(r.ok());
    EXPECT_FALSE(r->found) << "frame " << k;
    EXPECT_EQ(r->trajectory_frames, k + 1);
    if (k > 0) {
      EXPECT_NE(r->reason.find("frames' mean peaks: ambiguous"), std::string::npos) << r->reason;
    }
  }
  // The odometry says the camera moved 2 m: a new trajectory, this frame alone.
  const Result<Relocalization> r =
      (*relocalizer)
          ->Relocalize(renderer.Render(drive.truth[0], {0, 0}, 3).image,
                       geometry::Pose2{2.0, 0.0, 0.0});
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r->trajectory_frames, 1);
}

TEST(Relocalizer, NoIndexAndAMosaicTooLargeForTheDenseSearchIsRejected) {
  PlainScene scene = PlainConcreteScene();
  mosaic::ImageRasterSource floor(scene.photo,
                                  {0.0, scene.photo.rows * kResolutionM, kResolutionM});
  RelocalizerOptions options;
  options.dense.max_refine_level_mpx = 0.01;
  const auto refused = Relocalizer::Create(nullptr, &floor, scene.camera, options);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.status().message().find("no place index"), std::string::npos);
}

}  // namespace
}  // namespace fleetloc::relocalization
