// Landmark detection on rendered corridor scenes with known geometry (sim/corridor_scene.h): the
// visible floor-level corners are found to centimetres, the bin's slanted edges are rejected, and
// bad input is refused with clear messages.
#include "mapmatch/landmark_detector.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>

#include "sim/corridor_scene.h"
#include "sim/forward_renderer.h"

namespace fleetloc::mapmatch {
namespace {

// Corners whose edge the clean image shows with less contrast than this are not required.
constexpr double kMinContrastDn = 15.0;
constexpr double kDetectionRadiusM = 0.03;  // a corner is found within this
constexpr double kOutlierDistanceM = 0.10;  // a detection this far from every landmark is clutter

ForwardCamera PitchedCamera(double pitch_rad, double k1) {
  ForwardCameraParams p;
  p.K = {520, 0, 322.5, 0, 518, 238.75, 0, 0, 1};
  p.dist = {k1, 0.01, 2e-4, -1e-4, 0.0};
  p.mount = {.x_m = 0.45, .y_m = 0.02, .height_m = 1.0, .yaw_rad = 0.0, .pitch_rad = pitch_rad};
  return ForwardCamera::Create(p).value();
}

double Percentile(std::vector<double> values, double q) {
  std::sort(values.begin(), values.end());
  return values[static_cast<std::size_t>(q * (values.size() - 1))];
}

struct SceneStats {
  std::vector<double> corner_errors_m;  // per required corner: distance to the nearest detection
  int detections = 0;
  int outliers = 0;
};

// Renders `scenes` corridors from random poses and matches detections to the ground truth.
SceneStats RunScenes(const ForwardCamera& camera, int scenes, std::uint64_t first_seed) {
  const sim::ForwardRenderer renderer(camera, {});
  const LandmarkDetector detector = LandmarkDetector::Create(camera, {}).value();
  SceneStats stats;
  for (int k = 0; k < scenes; ++k) {
    sim::CorridorSceneOptions options;
    options.seed = first_seed + k;
    const sim::CorridorScene scene = sim::BuildCorridorScene(options);
    cv::RNG rng(options.seed);
    const geometry::Pose2 pose{rng.uniform(0.5, 9.0), rng.uniform(-0.5, 0.5),
                               rng.uniform(-0.35, 0.35)};
    const std::vector<FloorPointDetection> detections =
        detector.Detect(renderer.Render(scene, pose, options.seed)).value();
    const auto nearest = [&](const Eigen::Vector2d& point) {
      double best = std::numeric_limits<double>::infinity();
      for (const FloorPointDetection& d : detections)
        best = std::min(best, (d.point - point).norm());
      return best;
    };
    for (const sim::VisibleLandmark& v : renderer.VisibleLandmarks(scene, pose)) {
      if (v.range_m < 2.0 || v.range_m > 5.0 || v.contrast_dn < kMinContrastDn) continue;
      stats.corner_errors_m.push_back(nearest(v.base));
    }
    for (const FloorPointDetection& d : detections) {
      const bool near_a_landmark = std::any_of(
          scene.landmarks.begin(), scene.landmarks.end(), [&](const Eigen::Vector2d& l) {
            return (pose.Inverse() * l - d.point).norm() < kOutlierDistanceM;
          });
      stats.outliers += !near_a_landmark;
    }
    stats.detections += static_cast<int>(detections.size());
  }
  return stats;
}

void ExpectCornersFound(const SceneStats& stats, const char* camera_name) {
  const std::vector<double>& errors = stats.corner_errors_m;
  ASSERT_GE(errors.size(), 30u) << "too few corners in range to measure";
  const double found =
      static_cast<double>(std::count_if(errors.begin(), errors.end(),
                                        [](double e) { return e <= kDetectionRadiusM; })) /
      errors.size();
  const double outlier_fraction = static_cast<double>(stats.outliers) / stats.detections;
  std::cout << camera_name << ": " << errors.size() << " corners at 2-5 m, " << 100 * found
            << " % found within 3 cm, error median " << 1000 * Percentile(errors, 0.5)
            << " mm, 80th percentile " << 1000 * Percentile(errors, 0.8) << " mm; "
            << stats.detections << " detections, " << 100 * outlier_fraction
            << " % outliers (> 10 cm from every landmark)\n";
  // Measured here (16 scenes per camera): 84-85 % found, median 6-7 mm, 80th percentile 16-17 mm,
  // 36-42 % outliers; over 80 other scenes 91 % found. The misses: feet seen at grazing angles
  // (the floor boundary runs nearly along the edge), silhouettes against a background of similar
  // brightness, and edges continued by another edge below the corner.
  EXPECT_GE(found, 0.8);
  EXPECT_LE(Percentile(errors, 0.5), 0.010);
  EXPECT_LE(Percentile(errors, 0.8), 0.025);
  EXPECT_LE(outlier_fraction, 0.5);
}

TEST(LandmarkDetector, FindsTheVisibleCornersOfPitchedCameraScenesToCentimetres) {
  ExpectCornersFound(RunScenes(PitchedCamera(0.25, -0.08), 16, 100), "pitched 0.25 rad");
}

TEST(LandmarkDetector, FindsTheVisibleCornersWithANearlyLevelCamera) {
  ExpectCornersFound(RunScenes(PitchedCamera(0.08, -0.15), 16, 200), "pitched 0.08 rad");
}

// The bin stands on the floor but widens upward: its edges miss the nadir vanishing point.
TEST(LandmarkDetector, SlantedEdgesStandingOnTheFloorAreRejected) {
  sim::CorridorSceneOptions options;
  options.jitter_m = 0.0;  // the bin at (8.0, 0.5), 0.28 m wide at its foot
  const sim::CorridorScene scene = sim::BuildCorridorScene(options);
  const ForwardCamera camera = PitchedCamera(0.25, -0.08);
  const sim::ForwardRenderer renderer(camera, {.supersample = 1});
  const LandmarkDetector detector = LandmarkDetector::Create(camera, {}).value();
  const geometry::Pose2 pose{5.0, 0.4, 0.0};  // 2.5 m from the bin, looking at it
  const std::vector<FloorPointDetection> detections =
      detector.Detect(renderer.Render(scene, pose, 1)).value();
  ASSERT_FALSE(detections.empty());
  const Eigen::Vector2d bin = pose.Inverse() * Eigen::Vector2d(8.0, 0.5);
  for (const FloorPointDetection& d : detections) {
    EXPECT_GT((d.point - bin).norm(), 0.3) << "a detection at the bin: " << d.point.transpose();
  }
}

TEST(LandmarkDetector, SigmaGrowsAndQualityFallsWithRange) {
  const ForwardCamera camera = PitchedCamera(0.25, -0.08);
  const sim::ForwardRenderer renderer(camera, {.supersample = 1});
  const LandmarkDetector detector = LandmarkDetector::Create(camera, {}).value();
  const sim::CorridorScene scene = sim::BuildCorridorScene({});
  std::vector<FloorPointDetection> detections =
      detector.Detect(renderer.Render(scene, {1.0, 0.0, 0.0}, 1)).value();
  ASSERT_GE(detections.size(), 4u);
  std::sort(detections.begin(), detections.end(),
            [](const auto& a, const auto& b) { return a.range_m < b.range_m; });
  // The floor point's sensitivity to the foot grows about with the squared range.
  const FloorPointDetection& nearest = detections.front();
  const FloorPointDetection& farthest = detections.back();
  ASSERT_GT(farthest.range_m, 2 * nearest.range_m);
  EXPECT_GT(farthest.sigma_m, 2 * nearest.sigma_m);
  EXPECT_LT(farthest.quality, nearest.quality);
  for (const FloorPointDetection& d : detections) {
    EXPECT_GT(d.quality, 0.0);
    EXPECT_LE(d.quality, 1.0);
    EXPECT_GE(d.range_m, 0.3);
  }
}

TEST(LandmarkDetector, AFeaturelessImageGivesNoDetections) {
  const ForwardCamera camera = PitchedCamera(0.25, -0.08);
  const LandmarkDetector detector = LandmarkDetector::Create(camera, {}).value();
  cv::Mat image(camera.image_size(), CV_8UC1);
  cv::RNG(3).fill(image, cv::RNG::NORMAL, 120, 2);
  EXPECT_TRUE(detector.Detect(image).value().empty());
}

TEST(LandmarkDetector, BadImagesAreRefusedWithClearMessages) {
  const ForwardCamera camera = PitchedCamera(0.25, -0.08);
  const LandmarkDetector detector = LandmarkDetector::Create(camera, {}).value();
  const auto message = [&](const cv::Mat& image) {
    Result<std::vector<FloorPointDetection>> result = detector.Detect(image);
    EXPECT_FALSE(result.ok());
    EXPECT_EQ(result.status().code(), StatusCode::kInvalidInput);
    return result.status().message();
  };
  EXPECT_NE(message(cv::Mat()).find("empty"), std::string::npos);
  EXPECT_NE(message(cv::Mat(240, 320, CV_8UC1, cv::Scalar(0))).find("320×240 px"),
            std::string::npos);
  EXPECT_NE(message(cv::Mat(camera.image_size(), CV_16UC1, cv::Scalar(0))).find("8-bit"),
            std::string::npos);
  cv::Mat bgr(camera.image_size(), CV_8UC3, cv::Scalar(50, 50, 50));
  EXPECT_TRUE(detector.Detect(bgr).ok()) << "colour images are converted to gray";
}

TEST(LandmarkDetector, InvalidOptionsNameTheField) {
  const ForwardCamera camera = PitchedCamera(0.25, -0.08);
  LandmarkDetectorOptions options;
  options.canny_low = std::nan("");
  EXPECT_NE(LandmarkDetector::Create(camera, options).status().message().find("canny_low"),
            std::string::npos);
  options = {};
  options.max_range_m = options.min_range_m;
  EXPECT_NE(Validate(options).message().find("max_range_m"), std::string::npos);
  options = {};
  options.refinement.end_strength_fraction = 1.5;
  EXPECT_NE(Validate(options).message().find("refinement.end_strength_fraction"),
            std::string::npos);
  options = {};
  options.min_boundary_length_px = 100;
  EXPECT_NE(Validate(options).message().find("min_boundary_length_px"), std::string::npos);
}

TEST(LandmarkDetector, NanCameraParametersAreRefusedBeforeDetection) {
  ForwardCameraParams params;
  params.mount.pitch_rad = std::nan("");
  Result<ForwardCamera> camera = ForwardCamera::Create(params);
  ASSERT_FALSE(camera.ok());
  EXPECT_NE(camera.status().message().find("field 'mount.pitch'"), std::string::npos);
}

}  // namespace
}  // namespace fleetloc::mapmatch
