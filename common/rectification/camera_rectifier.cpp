// The rectifier of a camera.json: calibration::Rectifier from its raw block.
#include "rectification/camera_rectifier.h"

namespace fleetloc::rectification {

std::optional<calibration::Rectifier> RectifierFor(const run_io::CameraFile& camera) {
  if (!camera.raw) return std::nullopt;
  return calibration::Rectifier(cv::Matx33d(camera.raw->K.data()), camera.raw->dist,
                                cv::Matx33d(camera.raw->H_ground.data()), camera.model);
}

}  // namespace fleetloc::rectification
