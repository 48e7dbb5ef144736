// CheckCameraResolution: a relative comparison with the values in the message.
#include "tracking/camera_scale_check.h"

#include <charconv>
#include <cmath>

namespace fleetloc::tracking {
namespace {

// Shortest round-trip decimal text of `value` ("0.0005", as in camera.json and mosaic info).
std::string Shortest(double value) {
  char text[32];
  const auto [end, ec] = std::to_chars(text, text + sizeof text, value, std::chars_format::fixed);
  return ec == std::errc() ? std::string(text, end) : std::string("?");
}

}  // namespace

Status CheckCameraResolution(double camera_resolution_m, double mosaic_resolution_m,
                             const std::string& camera_source) {
  const double ratio = camera_resolution_m / mosaic_resolution_m;
  if (std::isfinite(ratio) && std::abs(ratio - 1.0) <= kMaxCameraResolutionMismatch)
    return Status::Ok();
  return InvalidInput(camera_source + ": camera resolution " + Shortest(camera_resolution_m) +
                      " m/px differs from the mosaic's " + Shortest(mosaic_resolution_m) +
                      " m/px by more than " +
                      std::to_string(static_cast<int>(kMaxCameraResolutionMismatch * 100)) +
                      " % (rectify the camera to the mosaic's resolution: fleetctl calibrate)");
}

}  // namespace fleetloc::tracking
