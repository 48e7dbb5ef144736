// A camera behind a GStreamer pipeline read through OpenCV's GStreamer backend: any V4L2/UVC
// camera (`v4l2src ...`), a GenICam camera through aravissrc, an RTSP stream, or frames from files
// (`multifilesrc ...`); the pipeline must end in an appsink. Frames are stamped with the buffer's
// timestamp (its position in the stream) mapped to the host clock (ClockMapper), or with the
// arrival time when the pipeline gives none.
#pragma once

#include <memory>
#include <opencv2/videoio.hpp>
#include <string>

#include "camera_io/camera_source.h"
#include "timing/clock_mapper.h"

namespace fleetloc::camera_io {

struct GstOptions {
  std::string pipeline;  // a gst-launch description ending in "appsink"
  // "buffer": the stream position OpenCV reports for the frame, mapped to the host clock;
  // "arrival": when it reached us; "frame_rate": the n-th frame (from 0) at
  // epoch_s + n / the caps' framerate, as multifilesrc stamps its buffers (files of a recorded run
  // whose first frame's time is known: its frames keep their recorded times, like replay).
  // OpenCV's position is the pipeline's, not the buffer's (opencv/opencv#19025): with sync=true
  // it trails the buffer by the processing delay (~10 ms measured here), hence the mapping.
  std::string timestamps = "buffer";
  double epoch_s = 0.0;
};

Status Validate(const GstOptions& options);

class GstCamera : public CameraSource {
 public:
  // Starts the pipeline. Internal when OpenCV cannot open it (bad description, missing plugin,
  // OpenCV without the GStreamer backend).
  static Result<std::unique_ptr<GstCamera>> Open(const GstOptions& options);

  // Blocks until the pipeline delivers a frame (OpenCV has no timeout: a stalled pipeline blocks
  // the caller's thread, which the live input watches). Internal at the end of the stream.
  Result<std::optional<CapturedFrame>> Grab(double timeout_s) override;
  CameraStats stats() const override { return stats_; }
  std::string Describe() const override { return "gstreamer pipeline '" + options_.pipeline + "'"; }

 private:
  explicit GstCamera(GstOptions options) : options_(std::move(options)) {}
  GstOptions options_;
  cv::VideoCapture capture_;
  timing::ClockMapper clock_;
  CameraStats stats_;
  double fps_ = 0.0;    // the caps' framerate (frame_rate timestamps)
  long long read_ = 0;  // frames read since the pipeline started
};

}  // namespace fleetloc::camera_io
