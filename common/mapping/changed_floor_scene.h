// Test scene shared by the re-mapping tests: a 1024² crop of a real floor photo whose floor
// "changed" in a known rectangle (another real texture pasted there), and patches of the changed
// floor cut at known places, reported with a known pose error.
#pragma once

#include <opencv2/imgcodecs.hpp>
#include <string>

#include "geometry/geotransform.h"
#include "mapping/patch_registration.h"

namespace fleetloc::mapping::testing {

inline cv::Mat LoadCrop(const char* path, const cv::Rect& crop) {
  cv::Mat gray = cv::imread(std::string(FLEETLOC_SOURCE_DIR) + "/" + path, cv::IMREAD_GRAYSCALE);
  return gray.empty() ? gray : gray(crop).clone();
}

struct ChangedFloorScene {
  static constexpr double kRes = 0.0005;
  cv::Mat old_floor = LoadCrop("deploy/demo/floors/rock_dirt_2048.png", {300, 300, 1024, 1024});
  cv::Mat new_floor;
  cv::Rect change{430, 380, 120, 90};  // where a new "marking" (another real texture) appears
  geometry::Geotransform geo{0.0, 1024 * kRes, kRes};

  ChangedFloorScene() {
    new_floor = old_floor.clone();
    LoadCrop("tests/data/brick.png", {0, 0, change.width, change.height}).copyTo(new_floor(change));
  }
  // A 320×240 patch of the new floor centred at pixel `centre`, reported off by `error`, with a
  // 3 px / 0.5° covariance.
  Patch PatchAt(cv::Point centre, const geometry::Pose2& error) const {
    const cv::Rect crop(centre.x - 160, centre.y - 120, 320, 240);
    const Eigen::Vector2d map = geo.PixelToMap({centre.x * 1.0, centre.y * 1.0});
    Patch p;
    p.image = new_floor(crop).clone();
    p.pose = {map.x() + error.x, map.y() + error.y, M_PI / 2 + error.theta};
    p.covariance =
        Eigen::Vector3d(std::pow(3 * kRes, 2), std::pow(3 * kRes, 2), std::pow(0.5 * M_PI / 180, 2))
            .asDiagonal();
    return p;
  }
};

}  // namespace fleetloc::mapping::testing
