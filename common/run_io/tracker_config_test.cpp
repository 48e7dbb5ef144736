// Tests for tracker options from JSON: defaults, overrides, unknown keys, types, ranges.
#include "run_io/tracker_config.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace fleetloc::run_io {
namespace {

TEST(TrackerConfig, EmptyObjectGivesDefaultsAndRoundTrips) {
  const auto options = TrackerOptionsFromJson(nlohmann::json::object(), "t.json");
  ASSERT_TRUE(options.ok());
  EXPECT_EQ(options->template_size_px, tracking::TrackerOptions{}.template_size_px);
  const auto again = TrackerOptionsFromJson(TrackerOptionsToJson(*options), "t.json");
  ASSERT_TRUE(again.ok());
  EXPECT_EQ(TrackerOptionsToJson(*again), TrackerOptionsToJson(*options));
}

TEST(TrackerConfig, OverridesNestedOdometryModel) {
  const auto options = TrackerOptionsFromJson(
      {{"max_templates", 32}, {"odometry", {{"along_sigma_per_m", 0.02}}}}, "t.json");
  ASSERT_TRUE(options.ok());
  EXPECT_EQ(options->max_templates, 32);
  EXPECT_DOUBLE_EQ(options->odometry.along_sigma_per_m, 0.02);
}

// The shipped examples (docs/formats.md) load and change what they say they change.
TEST(TrackerConfig, ShippedExamplesLoad) {
  const std::filesystem::path dir = FLEETLOC_SOURCE_DIR "/deploy/config/tracker";
  const auto light = ReadTrackerOptions(dir / "light_640.json");
  ASSERT_TRUE(light.ok()) << light.status().message();
  EXPECT_LT(light->polish_max_frame_pixels, 640 * 480);
  const auto precise = ReadTrackerOptions(dir / "precise_640.json");
  ASSERT_TRUE(precise.ok()) << precise.status().message();
  EXPECT_EQ(precise->direct.polish_max_level, 0);
  EXPECT_GE(precise->polish_max_frame_pixels, 640 * 480);
}

TEST(TrackerConfig, RejectsUnknownWrongTypeAndOutOfRange) {
  auto bad = TrackerOptionsFromJson({{"max_templats", 32}}, "t.json");
  EXPECT_EQ(bad.status().message(), "t.json: field 'max_templats': unknown option");
  bad = TrackerOptionsFromJson({{"max_templates", 3.5}}, "t.json");
  EXPECT_EQ(bad.status().message(), "t.json: field 'max_templates': must be an integer");
  bad = TrackerOptionsFromJson({{"odometry", {{"along", 1}}}}, "t.json");
  EXPECT_EQ(bad.status().message(), "t.json: field 'odometry.along': unknown option");
  bad = TrackerOptionsFromJson({{"template_size_px", 31}}, "t.json");
  EXPECT_EQ(bad.status().code(), StatusCode::kInvalidInput);
  EXPECT_NE(bad.status().message().find("template_size_px"), std::string::npos);
}

TEST(TrackerConfig, ReadsTheTextureCapAndRefusesOneOutsideAQuantile) {
  EXPECT_DOUBLE_EQ(TrackerOptionsFromJson(nlohmann::json::object(), "t.json")->texture_cap_quantile,
                   0.5);
  const auto off = TrackerOptionsFromJson({{"texture_cap_quantile", 0}}, "t.json");
  ASSERT_TRUE(off.ok());
  EXPECT_EQ(off->texture_cap_quantile, 0.0);
  for (const double q : {-0.1, 1.0}) {
    const auto bad = TrackerOptionsFromJson({{"texture_cap_quantile", q}}, "t.json");
    EXPECT_EQ(bad.status().code(), StatusCode::kInvalidInput) << q;
    EXPECT_NE(bad.status().message().find("texture_cap_quantile"), std::string::npos);
  }
}

TEST(TrackerConfig, ReadsThePolishOptionsAndRefusesASinglePassBeyondTheConvergenceGate) {
  const auto options = TrackerOptionsFromJson(
      {{"polish_dense_max_frame_pixels", 0}, {"direct", {{"polish_single_pass_px", 0.2}}}},
      "t.json");
  ASSERT_TRUE(options.ok());
  EXPECT_EQ(options->polish_dense_max_frame_pixels, 0);
  EXPECT_DOUBLE_EQ(options->direct.polish_single_pass_px, 0.2);
  EXPECT_TRUE(options->direct.noise_model);  // the default
  const auto equal_weights =
      TrackerOptionsFromJson({{"direct", {{"noise_model", false}}}}, "t.json");
  ASSERT_TRUE(equal_weights.ok());
  EXPECT_FALSE(equal_weights->direct.noise_model);
  EXPECT_EQ(TrackerOptionsFromJson({{"direct", {{"noise_model", 1.5}}}}, "t.json").status().code(),
            StatusCode::kInvalidInput);
  // A single pass that may move further than a converged polish's next step would contradict it.
  const auto bad = TrackerOptionsFromJson(
      {{"direct", {{"polish_single_pass_px", 0.5}, {"max_polish_next_step_px", 0.35}}}}, "t.json");
  EXPECT_EQ(bad.status().code(), StatusCode::kInvalidInput);
  EXPECT_NE(bad.status().message().find("direct.polish_single_pass_px"), std::string::npos);
}

TEST(TrackerConfig, ReadsThePolishedCamerasTemplatesAndLevelAndRefusesTooFew) {
  const auto options = TrackerOptionsFromJson(
      {{"polished_max_templates", 14}, {"direct", {{"polish_max_level", 0}}}}, "t.json");
  ASSERT_TRUE(options.ok());
  EXPECT_EQ(options->polished_max_templates, 14);
  EXPECT_EQ(options->direct.polish_max_level, 0);
  // Fewer templates than a lock needs could never lock.
  auto bad = TrackerOptionsFromJson({{"polished_max_templates", 3}, {"min_inliers", 4}}, "t.json");
  EXPECT_EQ(bad.status().code(), StatusCode::kInvalidInput);
  EXPECT_NE(bad.status().message().find("polished_max_templates"), std::string::npos);
  bad = TrackerOptionsFromJson({{"direct", {{"polish_max_level", -1}}}}, "t.json");
  EXPECT_NE(bad.status().message().find("direct.polish_max_level"), std::string::npos);
}

TEST(TrackerConfig, ReadsTheConfirmingPolishAndRefusesAWeakFitFloorAboveTheSignificantOne) {
  const auto options = TrackerOptionsFromJson(
      {{"direct",
        {{"min_polished_significant_correlation", 0.2}, {"confirm_polish_iterations", 3}}}},
      "t.json");
  ASSERT_TRUE(options.ok());
  EXPECT_DOUBLE_EQ(options->direct.min_polished_significant_correlation, 0.2);
  EXPECT_EQ(options->direct.confirm_polish_iterations, 3);
  // Above min_significant_correlation it would ask the polish to confirm fits valid without it.
  auto bad = TrackerOptionsFromJson({{"direct", {{"min_polished_significant_correlation", 0.4}}}},
                                    "t.json");
  EXPECT_EQ(bad.status().code(), StatusCode::kInvalidInput);
  EXPECT_NE(bad.status().message().find("direct.min_polished_significant_correlation"),
            std::string::npos);
  bad = TrackerOptionsFromJson({{"direct", {{"confirm_polish_iterations", -1}}}}, "t.json");
  EXPECT_NE(bad.status().message().find("direct.confirm_polish_iterations"), std::string::npos);
}

TEST(TrackerConfig, ReadsTheRefinePassWindowAndRefusesOneWiderThanTheFinePasses) {
  const auto options = TrackerOptionsFromJson({{"refine_pass_radius_px", 2}}, "t.json");
  ASSERT_TRUE(options.ok());
  EXPECT_EQ(options->refine_pass_radius_px, 2);
  EXPECT_EQ(tracking::TrackerOptions{}.refine_pass_radius_px, 1);
  const auto bad = TrackerOptionsFromJson({{"refine_pass_radius_px", 3}}, "t.json");
  EXPECT_EQ(bad.status().code(), StatusCode::kInvalidInput);
  EXPECT_NE(bad.status().message().find("refine_pass_radius_px"), std::string::npos);
}

TEST(TrackerConfig, ReadsTheHeadingProbesWindowAndRefusesANegativeOne) {
  const auto options = TrackerOptionsFromJson({{"direct", {{"heading_probe_px", 0}}}}, "t.json");
  ASSERT_TRUE(options.ok());
  EXPECT_EQ(options->direct.heading_probe_px, 0);
  EXPECT_EQ(tracking::TrackerOptions{}.direct.heading_probe_px, 2);
  const auto bad = TrackerOptionsFromJson({{"direct", {{"heading_probe_px", -1}}}}, "t.json");
  EXPECT_EQ(bad.status().code(), StatusCode::kInvalidInput);
  EXPECT_NE(bad.status().message().find("direct.heading_probe_px"), std::string::npos);
}

TEST(TrackerConfig, ReadsTheTentativePeakFloorAndRefusesANegativeOne) {
  const auto options =
      TrackerOptionsFromJson({{"direct", {{"min_tentative_peak_z", 0}}}}, "t.json");
  ASSERT_TRUE(options.ok());
  EXPECT_EQ(options->direct.min_tentative_peak_z, 0.0);
  EXPECT_EQ(tracking::TrackerOptions{}.direct.min_tentative_peak_z, 4.0);
  const auto bad = TrackerOptionsFromJson({{"direct", {{"min_tentative_peak_z", -1}}}}, "t.json");
  EXPECT_EQ(bad.status().code(), StatusCode::kInvalidInput);
  EXPECT_NE(bad.status().message().find("direct.min_tentative_peak_z"), std::string::npos);
}

TEST(TrackerConfig, ReadsThePolishsWideWindowAndRefusesANegativeOneOrNoMargin) {
  const auto options = TrackerOptionsFromJson(
      {{"direct", {{"polish_wide_window_px", 0}, {"polish_wide_window_max_sigma_ratio", 0.8}}}},
      "t.json");
  ASSERT_TRUE(options.ok());
  EXPECT_EQ(options->direct.polish_wide_window_px, 0);
  EXPECT_EQ(options->direct.polish_wide_window_max_sigma_ratio, 0.8);
  EXPECT_EQ(tracking::TrackerOptions{}.direct.polish_wide_window_px, 15);
  for (const auto& [key, value] : std::vector<std::pair<std::string, double>>{
           {"polish_wide_window_px", -1}, {"polish_wide_window_max_sigma_ratio", 0}}) {
    const auto bad = TrackerOptionsFromJson({{"direct", {{key, value}}}}, "t.json");
    EXPECT_EQ(bad.status().code(), StatusCode::kInvalidInput) << key;
    EXPECT_NE(bad.status().message().find("direct." + key), std::string::npos) << key;
  }
}

TEST(TrackerConfig, ReadsThePolishsUnsmoothedRatioAndRefusesANegativeOne) {
  const auto options =
      TrackerOptionsFromJson({{"direct", {{"polish_unsmoothed_max_sigma_ratio", 0}}}}, "t.json");
  ASSERT_TRUE(options.ok());
  EXPECT_EQ(options->direct.polish_unsmoothed_max_sigma_ratio, 0.0);
  EXPECT_EQ(tracking::TrackerOptions{}.direct.polish_unsmoothed_max_sigma_ratio, 1.1);
  const auto bad =
      TrackerOptionsFromJson({{"direct", {{"polish_unsmoothed_max_sigma_ratio", -0.5}}}}, "t.json");
  EXPECT_EQ(bad.status().code(), StatusCode::kInvalidInput);
  EXPECT_NE(bad.status().message().find("direct.polish_unsmoothed_max_sigma_ratio"),
            std::string::npos);
}

TEST(TrackerConfig, ReadsThePolishLevelAndLargeCameraOptionsAndRefusesNegativeOnes) {
  const auto options = TrackerOptionsFromJson(
      {{"polish_min_frame_pixels", 0}, {"direct", {{"polish_max_level_pixels", 0}}}}, "t.json");
  ASSERT_TRUE(options.ok());
  EXPECT_EQ(options->polish_min_frame_pixels, 0);
  EXPECT_EQ(options->direct.polish_max_level_pixels, 0);
  const tracking::TrackerOptions defaults;
  EXPECT_EQ(defaults.polish_min_frame_pixels, 1000000);
  EXPECT_EQ(defaults.direct.polish_max_level_pixels, 80000);
  EXPECT_EQ(defaults.direct.polish_max_level, 1);
  EXPECT_EQ(defaults.polish_max_frame_pixels, 307200);  // 320×240 and 640×480 polish every frame
  auto bad = TrackerOptionsFromJson({{"polish_min_frame_pixels", -1}}, "t.json");
  EXPECT_EQ(bad.status().code(), StatusCode::kInvalidInput);
  EXPECT_NE(bad.status().message().find("polish_min_frame_pixels"), std::string::npos);
  bad = TrackerOptionsFromJson({{"direct", {{"polish_max_level_pixels", -5}}}}, "t.json");
  EXPECT_EQ(bad.status().code(), StatusCode::kInvalidInput);
  EXPECT_NE(bad.status().message().find("direct.polish_max_level_pixels"), std::string::npos);
  EXPECT_EQ(defaults.polish_dense_max_level_pixels, 80000);
  EXPECT_EQ(TrackerOptionsFromJson({{"polish_dense_max_level_pixels", 0}}, "t.json")
                ->polish_dense_max_level_pixels,
            0);
  bad = TrackerOptionsFromJson({{"polish_dense_max_level_pixels", -1}}, "t.json");
  EXPECT_EQ(bad.status().code(), StatusCode::kInvalidInput);
  EXPECT_NE(bad.status().message().find("polish_dense_max_level_pixels"), std::string::npos);
}

}  // namespace
}  // namespace fleetloc::run_io
