// OpenCV's CAP_GSTREAMER behind CameraSource.
#include "camera_io/gst_camera.h"

#include <cmath>
#include <opencv2/imgproc.hpp>

namespace fleetloc::camera_io {

Status Validate(const GstOptions& o) {
  if (o.pipeline.find("appsink") == std::string::npos) {
    return InvalidInput("field 'gstreamer.pipeline': must end in an appsink");
  }
  if (o.timestamps != "buffer" && o.timestamps != "arrival" && o.timestamps != "frame_rate") {
    return InvalidInput("field 'gstreamer.timestamps': must be buffer, arrival or frame_rate");
  }
  if (!std::isfinite(o.epoch_s)) return InvalidInput("field 'gstreamer.epoch_s': must be finite");
  return Status::Ok();
}

Result<std::unique_ptr<GstCamera>> GstCamera::Open(const GstOptions& options) {
  FLEETLOC_RETURN_IF_ERROR(Validate(options));
  std::unique_ptr<GstCamera> cam(new GstCamera(options));
  try {
    if (!cam->capture_.open(options.pipeline, cv::CAP_GSTREAMER)) {
      return Internal("gstreamer: cannot start pipeline '" + options.pipeline + "'");
    }
    cam->fps_ = cam->capture_.get(cv::CAP_PROP_FPS);
    if (options.timestamps == "frame_rate" && !(cam->fps_ > 0)) {
      return Internal("gstreamer: pipeline '" + options.pipeline +
                      "' has no framerate in its caps");
    }
  } catch (const cv::Exception& e) {
    return Internal("gstreamer: pipeline '" + options.pipeline + "': " + e.what());
  }
  return cam;
}

Result<std::optional<CapturedFrame>> GstCamera::Grab(double /*timeout_s*/) {
  cv::Mat image;
  try {
    if (!capture_.read(image) || image.empty()) return Internal(Describe() + ": end of stream");
  } catch (const cv::Exception& e) {
    return Internal(Describe() + ": " + e.what());
  }
  ++read_;  // frames read since the pipeline started, dropped or not
  const long long n = read_ - 1;
  CapturedFrame frame;
  frame.arrival_t = HostNow();
  if (image.channels() == 3) {
    cv::cvtColor(image, frame.image, cv::COLOR_BGR2GRAY);
  } else if (image.type() == CV_8UC1) {
    frame.image = image.clone();
  } else {
    ++stats_.dropped;
    stats_.last_drop =
        "frame of OpenCV type " + std::to_string(image.type()) + " (want 8-bit gray or BGR)";
    return std::optional<CapturedFrame>();
  }
  // The buffer's stream position (OpenCV's POS_MSEC), when the pipeline stamps its buffers.
  if (options_.timestamps == "frame_rate") {
    frame.t = options_.epoch_s + static_cast<double>(n) / fps_;
  } else {
    const double position_ms =
        options_.timestamps == "buffer" ? capture_.get(cv::CAP_PROP_POS_MSEC) : -1;
    frame.t =
        position_ms >= 0 ? clock_.Map(position_ms / 1000.0, frame.arrival_t) : frame.arrival_t;
  }
  ++stats_.frames;
  return std::optional<CapturedFrame>(std::move(frame));
}

}  // namespace fleetloc::camera_io
