// Test helper: the patches a forged (or badly broken) vehicle sends over the changed-floor scene,
// each claiming a perfect pose (a tiny, positive definite covariance and quality 1), none of them
// a true view of the floor where it claims to be. Shared by the admission, re-mapping and map
// server tests.
#pragma once

#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "mapping/changed_floor_scene.h"

namespace fleetloc::mapping::testing {

struct ForgedPatch {
  std::string kind;  // "garbage", "flat", "shifted", "shifted_far", "checkerboard", "flattened"
  Patch patch;
};

// σ = 0.01 px and 0.001°: "perfect", yet well formed (zero is refused as malformed on arrival).
inline Eigen::Matrix3d PerfectCovariance() {
  return Eigen::Vector3d(std::pow(0.01 * ChangedFloorScene::kRes, 2),
                         std::pow(0.01 * ChangedFloorScene::kRes, 2),
                         std::pow(0.001 * M_PI / 180, 2))
      .asDiagonal();
}

inline cv::Mat Checkerboard(cv::Size size, int square_px) {
  cv::Mat board(size, CV_8UC1);
  for (int y = 0; y < size.height; ++y) {
    for (int x = 0; x < size.width; ++x) {
      board.at<uchar>(y, x) = ((x / square_px + y / square_px) % 2) ? 230 : 25;
    }
  }
  return board;
}

// The forgeries, each claiming to show the floor around pixel `centre` of the scene.
inline std::vector<ForgedPatch> ForgedPatches(const ChangedFloorScene& scene, cv::Point centre,
                                              const std::string& vehicle = "forger") {
  const cv::Size size(320, 240);
  auto at = [&](cv::Mat image, cv::Point claimed) {
    Patch p = scene.PatchAt(claimed, {});
    p.image = std::move(image);
    p.covariance = PerfectCovariance();
    p.quality = 1.0;
    p.vehicle_id = vehicle;
    return p;
  };
  auto crop = [&](const cv::Mat& floor, cv::Point c) {
    return floor(cv::Rect(c.x - size.width / 2, c.y - size.height / 2, size.width, size.height))
        .clone();
  };
  cv::Mat garbage(size, CV_8UC1);
  cv::randu(garbage, 0, 256);
  cv::Mat flattened = crop(scene.old_floor, centre);
  flattened(cv::Rect(40, 30, 240, 180)).setTo(cv::mean(flattened)[0]);  // 56 % of it
  return {
      {"garbage", at(garbage, centre)},
      {"flat", at(cv::Mat(size, CV_8UC1, cv::Scalar(128)), centre)},
      // Real floor, reported 8 px (inside the server's search) and 60 px (outside it) off.
      {"shifted", at(crop(scene.new_floor, centre + cv::Point(8, 0)), centre)},
      {"shifted_far", at(crop(scene.old_floor, centre + cv::Point(60, 40)), centre)},
      {"checkerboard", at(Checkerboard(size, 16), centre)},
      // Real floor at its true place with more than half of it wiped flat.
      {"flattened", at(flattened, centre)},
  };
}

// Real floor at its true place with a checkerboard "marking" pasted over a third of it: it
// registers and its change looks plausible; only another vehicle's view can refute it.
inline Patch SplicedPatch(const ChangedFloorScene& scene, cv::Point centre,
                          const std::string& vehicle) {
  Patch p = scene.PatchAt(centre, {});
  p.image = scene.old_floor(cv::Rect(centre.x - 160, centre.y - 120, 320, 240)).clone();
  Checkerboard({96, 96}, 12).copyTo(p.image(cv::Rect(112, 72, 96, 96)));
  p.covariance = PerfectCovariance();
  p.quality = 1.0;
  p.vehicle_id = vehicle;
  return p;
}

}  // namespace fleetloc::mapping::testing
